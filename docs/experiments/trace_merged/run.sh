#!/bin/bash
# PERF.md step 39: main with TRACE_MERGED (one traversal in each trace kernel of a merged
# scene) on the GPU machine: `raygraph selftest`, then `bench rays --frames 10`, Table 3 and
# the real assets (the helmet and the pine at their cameras and at 2%, 5%, 10% of the frame;
# helmet_5x5x5 left out for the device time left), both back-ends. One release binary
# (.gpu/raygraph.xz), this checkout's files. Results in $OUT/trace_merged.tgz.
NAME=trace_merged EXTRA= bash docs/experiments/net_reinsert/run.sh
