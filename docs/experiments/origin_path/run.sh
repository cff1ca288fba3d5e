#!/bin/bash
# PERF.md step 42: a lane's AO rays descend the nodes that hold their origin once
# (`origin_path`: trace_origin_path), against main. Made by `bash
# docs/experiments/low_coverage/pack.sh REV docs/experiments/origin_path origin_path`. The
# driver's statistics of each kernel (`render --kernel-stats`: the atrium's and the pine's
# scene workloads), then `bench rays --backend compute --frames 10`: Table 3 (main,
# origin_path, main) and the real assets (main, origin_path). One release binary
# (.gpu/raygraph.xz). Results in $OUT/origin_path.tgz.
. docs/experiments/low_coverage/preamble.sh
for v in main origin_path; do
  kstats $v atrium --scene atrium --graph graph/bench_rays.ron
  kstats $v pine --scene $ROOT/assets/gltf/smallpine/scene.gltf --graph graph/bench_rays.ron
done
for v in main origin_path main; do bench $v table3; done
for v in main origin_path; do bench $v real; done
cd $OUT && tar czf origin_path.tgz r && rm -rf r
