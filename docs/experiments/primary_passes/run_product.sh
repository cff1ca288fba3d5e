#!/bin/bash
# PERF.md step 51: primary rays that pass BLEND surfaces in one traversal (TRACE_PASS_BLEND).
# On the GPU machine, one release binary (.gpu/raygraph.xz) and this checkout as it is:
# `raygraph selftest`, then `bench rays --frames 10` on both back-ends on the real assets (the
# helmet, the pine and helmet_5x5x5 at their cameras and at 2%, 5%, 10% of the frame; Table 3's
# scenes have no BLEND material, so the flag is a constant zero there and they are left out).
# .gpu/diag.tgz is unpacked but not used. Results in $OUT/pass_blend.tgz.
. docs/experiments/low_coverage/preamble.sh
selftest
export_copies
bench_both real
cd $OUT && tar czf pass_blend.tgz r && rm -rf r
