#!/bin/bash
# PERF.md step 36: what the driver compiled the trace kernels into (`render --kernel-stats`:
# registers and whatever else the driver reports), for main's shaders and step 35's variants
# (docs/experiments/live_state, packed by `bash docs/experiments/low_coverage/pack.sh REV
# docs/experiments/live_state all merged_path start_extent rows_at_leaf merged_extent`): the
# atrium's scene workload (G-buffer primary rays, shadow, AO), the primary tests' kernel
# (graph/bench_primary.ron: Stress, Miss) and the pine's scene workload (alpha-tested).
# One frame each at 320x180 (the statistics do not depend on the size). One release binary
# (.gpu/raygraph.xz). Results in $OUT/kernel_stats.tgz; a summary printed last.
. docs/experiments/low_coverage/preamble.sh
PINE=$ROOT/assets/gltf/smallpine/scene.gltf
for v in main merged_path start_extent rows_at_leaf merged_extent all; do
  for what in atrium primary pine; do
    case $what in
      atrium) args="--scene atrium --graph graph/bench_rays.ron" ;;
      primary) args="--scene atrium --graph graph/bench_primary.ron" ;;
      pine) args="--scene $PINE --graph graph/bench_rays.ron" ;;
    esac
    (cd /tmp/v/$v && timeout 120 $RG render $args --backend compute --width 320 --height 180 --frames 1 \
      --out $OUT/r/${v}_$what.png --kernel-stats $OUT/r/${v}_$what.md > $OUT/r/${v}_$what.log 2>&1) || tail -3 $OUT/r/${v}_$what.log
  done
done
cat $OUT/r/main_atrium.md | head -40
for f in $OUT/r/*.md; do
  echo "== $(basename $f .md)"
  awk '/^## /{k=$2} /^\| / && tolower($0) ~ /register|spill|local|instruction|binary|shared/ {print "  " k " " $0}' $f | sort -u
done
cd $OUT && tar czf kernel_stats.tgz r && rm -rf r
