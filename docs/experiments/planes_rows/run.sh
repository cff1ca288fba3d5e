#!/bin/bash
# PERF.md step 40: two changes to compute.wgsl that change no result, each against main:
# `octant_planes` (each axis's entry and exit planes picked by per-ray multipliers, the slab's
# min and max of both planes' t gone) and `late_rows` (the watertight test's rows formed after
# the root's box is hit, TRACE_MERGED). Made by `bash docs/experiments/low_coverage/pack.sh REV
# docs/experiments/planes_rows octant_planes late_rows`. The driver's statistics of each
# kernel (`render --kernel-stats`), then `bench rays --backend compute --frames 10`: Table 3
# (main, octant_planes, late_rows, main) and the real assets (main, octant_planes, late_rows).
# One release binary (.gpu/raygraph.xz). Results in $OUT/planes_rows.tgz.
. docs/experiments/low_coverage/preamble.sh
for v in main octant_planes late_rows; do
  kstats $v atrium --scene atrium --graph graph/bench_rays.ron
  kstats $v primary --scene atrium --graph graph/bench_primary.ron
done
for v in main octant_planes late_rows main; do bench $v table3; done
for v in main octant_planes late_rows; do bench $v real; done
cd $OUT && tar czf planes_rows.tgz r && rm -rf r
