//! Fuzz target: arbitrary bytes as a track file (see `raygraph::fuzz::track_file`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = raygraph::fuzz::track_file(data);
});
