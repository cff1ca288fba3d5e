#!/bin/bash
# PERF.md step 37: the AO, shadow and primary tests' kernels in 1024-invocation workgroups, so
# that the driver compiles them within 64 registers a lane (variants in
# docs/experiments/live_state/variants: `wg1024`, `rows_wg1024` with `rows_at_leaf`). Made by
# `bash docs/experiments/low_coverage/pack.sh REV docs/experiments/live_state wg1024
# rows_wg1024`. First the driver's statistics of each kernel (`render --kernel-stats`), then
# `bench rays --backend compute --frames 10`: Table 3 for main, both variants and main again;
# the real assets (the helmet, the pine, at their cameras and at 2%, 5%, 10% of the frame) for
# main, `wg1024`, `rows_wg1024`. One release binary (.gpu/raygraph.xz). Results in
# $OUT/wg1024.tgz.
. docs/experiments/low_coverage/preamble.sh
for v in main wg1024 rows_wg1024; do
  kstats $v atrium --scene atrium --graph graph/bench_rays.ron
  kstats $v primary --scene atrium --graph graph/bench_primary.ron
done
bench main table3; bench wg1024 table3; bench rows_wg1024 table3; bench main table3
bench main real; bench wg1024 real; bench rows_wg1024 real
cd $OUT && tar czf wg1024.tgz r && rm -rf r
