//! Fuzz target: arbitrary bytes as a scene file (see `raygraph::fuzz::scene_file`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = raygraph::fuzz::scene_file(data);
});
