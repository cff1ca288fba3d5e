//! Fuzz target: arbitrary bytes as a layer file (see `raygraph::fuzz::layer_file`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = raygraph::fuzz::layer_file(data);
});
