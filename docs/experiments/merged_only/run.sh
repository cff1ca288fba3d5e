#!/bin/bash
# PERF.md step 38: one traversal in each trace kernel, the merged instance's BLAS loop
# (docs/experiments/live_state/variants/merged_only.patch; diagnostic, right for merged scenes
# only, which every scene here is). Made by `bash docs/experiments/low_coverage/pack.sh REV
# docs/experiments/live_state merged_only`. The driver's statistics of each kernel
# (`render --kernel-stats`: the atrium's scene workload, the primary tests' kernel, the pine's
# scene workload), then `bench rays --backend compute --frames 10`, Table 3 and the real assets
# (the helmet, the pine, at their cameras and at 2%, 5%, 10% of the frame): main, merged_only,
# main. One release binary (.gpu/raygraph.xz). Results in $OUT/merged_only.tgz.
. docs/experiments/low_coverage/preamble.sh
for v in main merged_only; do
  kstats $v atrium --scene atrium --graph graph/bench_rays.ron
  kstats $v primary --scene atrium --graph graph/bench_primary.ron
  kstats $v pine --scene $ROOT/assets/gltf/smallpine/scene.gltf --graph graph/bench_rays.ron
done
for v in main merged_only main; do bench $v table3; bench $v real; done
cd $OUT && tar czf merged_only.tgz r && rm -rf r
