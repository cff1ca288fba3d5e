//! Fuzz target: arbitrary bytes as a graph file (see `raygraph::fuzz::graph_file`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = raygraph::fuzz::graph_file(data);
});
