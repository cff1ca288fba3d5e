#!/bin/bash
# PERF.md step 36: what the driver compiled the trace kernels into (`render --kernel-stats`:
# registers and whatever else the driver reports), for main's shaders and step 35's variants
# (docs/experiments/live_state, packed by `bash docs/experiments/low_coverage/pack.sh REV
# docs/experiments/live_state all merged_path start_extent rows_at_leaf merged_extent`): the
# atrium's scene workload (G-buffer primary rays, shadow, AO), the primary tests' kernel
# (graph/bench_primary.ron: Stress, Miss) and the pine's scene workload (alpha-tested).
# One frame each at 320x180 (the statistics do not depend on the size). One release binary
# (.gpu/raygraph.xz). Results in $OUT/kernel_stats.tgz; each kernel's registers printed as it goes.
. docs/experiments/low_coverage/preamble.sh
for v in main merged_path start_extent rows_at_leaf merged_extent all; do
  kstats $v atrium --scene atrium --graph graph/bench_rays.ron
  kstats $v primary --scene atrium --graph graph/bench_primary.ron
  kstats $v pine --scene $ROOT/assets/gltf/smallpine/scene.gltf --graph graph/bench_rays.ron
done
head -40 $OUT/r/main_atrium.md
cd $OUT && tar czf kernel_stats.tgz r && rm -rf r
