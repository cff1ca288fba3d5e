#!/bin/bash
# PERF.md step 43: a lane's AO rays without the test that their segment stays in the start's
# box (`no_segment`; their reach is the box's radius and their directions unit vectors, so it
# always passes), against main. Made by `bash docs/experiments/low_coverage/pack.sh REV
# docs/experiments/no_segment no_segment`. The driver's statistics of each kernel (`render
# --kernel-stats`: the atrium's and the pine's scene workloads), then `bench rays --backend
# compute --frames 10`: Table 3 and the real assets, main then no_segment. One release binary
# (.gpu/raygraph.xz). Results in $OUT/no_segment.tgz.
. docs/experiments/low_coverage/preamble.sh
for v in main no_segment; do
  kstats $v atrium --scene atrium --graph graph/bench_rays.ron
  kstats $v pine --scene $ROOT/assets/gltf/smallpine/scene.gltf --graph graph/bench_rays.ron
done
for v in main no_segment; do bench $v table3; done
for v in main no_segment; do bench $v real; done
cd $OUT && tar czf no_segment.tgz r && rm -rf r
