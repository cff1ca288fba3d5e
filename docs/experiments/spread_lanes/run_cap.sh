#!/bin/bash
# PERF.md step 49: at most 16 lanes a pixel in the spread AO schedule. On the GPU machine, one
# release binary (.gpu/raygraph.xz): the real assets (the helmet, the pine and helmet_5x5x5 at
# their cameras and at 2%, 5%, 10% of the frame) with `bench rays --backend compute --frames 10`
# on main's shaders before the cap (the folder `main` of .gpu/diag.tgz, made by `bash
# docs/experiments/low_coverage/pack.sh c1c7028 docs/experiments/spread_lanes`), then this
# checkout as it is (`shipped`: selftest, both back-ends on Table 3 and the real assets).
# Results in $OUT/spread_cap.tgz.
. docs/experiments/low_coverage/preamble.sh
export_copies
REAL=$REAL_ALL
bench main real
shipped
cd $OUT && tar czf spread_cap.tgz r && rm -rf r
