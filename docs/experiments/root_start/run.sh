#!/bin/bash
# PERF.md step 41: the AO rays of a scene that starts them at the root (TRACE_START_BELOW_ROOT
# off: the box) without the start box's segment test (`root_first`), against main. Made by
# `bash docs/experiments/low_coverage/pack.sh REV docs/experiments/root_start root_first`. The
# driver's statistics of each kernel (`render --kernel-stats`: the box's and the atrium's scene
# workloads), then `bench rays --backend compute --frames 10`, Table 3: main, root_first, main.
# One release binary (.gpu/raygraph.xz). Results in $OUT/root_start.tgz.
. docs/experiments/low_coverage/preamble.sh
for v in main root_first; do
  kstats $v box --scene box --graph graph/bench_rays.ron
  kstats $v atrium --scene atrium --graph graph/bench_rays.ron
done
for v in main root_first main; do bench $v table3; done
cd $OUT && tar czf root_start.tgz r && rm -rf r
