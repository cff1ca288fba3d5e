#!/bin/bash
# PERF.md step 62: registers and local memory of the trace kernels of main, `step4`,
# `step4_sorted` and `step4_pushed` (`render --kernel-stats`, one 320x180 frame of the atrium
# through graph/bench_rays.ron, compute). Made by `bash docs/experiments/low_coverage/pack.sh
# b7e8a9d docs/experiments/wide_step step4 step4_sorted step4_pushed`. Results in
# $OUT/wide_step_kstats.tgz.
. docs/experiments/low_coverage/preamble.sh
for v in main step4 step4_sorted step4_pushed; do kstats $v atrium --graph graph/bench_rays.ron --scene atrium; done
cd $OUT && tar czf wide_step_kstats.tgz r && rm -rf r
