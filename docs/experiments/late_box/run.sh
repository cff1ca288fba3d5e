#!/bin/bash
# PERF.md step 40, kept: the root's box tested before the watertight test's rows are formed
# (trace_merged). On the GPU machine, one release binary (.gpu/raygraph.xz): the driver's
# statistics of the trace kernels before (`main`: the files of the commit before) and after
# (`late_box`: this checkout's), `raygraph selftest`, then `bench rays --frames 10` on this
# checkout, Table 3 and the real assets (the helmet, the pine and helmet_5x5x5 at their cameras
# and at 2%, 5%, 10% of the frame), both back-ends; last, Table 3 before, compute only.
# Made by `bash docs/experiments/low_coverage/pack.sh 9a7ce72 docs/experiments/planes_rows
# late_box`. Results in $OUT/late_box.tgz.
. docs/experiments/low_coverage/preamble.sh
for v in main late_box; do
  kstats $v atrium --scene atrium --graph graph/bench_rays.ron
  kstats $v primary --scene atrium --graph graph/bench_primary.ron
done
shipped
bench main table3
cd $OUT && tar czf late_box.tgz r && rm -rf r
