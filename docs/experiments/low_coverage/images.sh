#!/bin/bash
# The lavapipe check that a variant changes no result: renders, with this checkout's release
# binary and the compute back-end at 320x180, each folder pack.sh made (/tmp/diag_trees/NAME:
# main and the variants) and compares every image with main's byte for byte. The atrium, the
# helmet, the pine and the box through graph/bench_rays.ron, the atrium through
# graph/bench_primary.ron, full RT on the atrium, hybrid on the default scene and on
# atrium-moving. `images.sh VARIANT...`; prints one line per image, "same" or "DIFFERENT".
set -u
cd "$(dirname "$0")/../../.."
RG=$PWD/target/release/raygraph
A=$PWD/assets/gltf
cases=(
  "rays_atrium --scene atrium --graph graph/bench_rays.ron"
  "rays_helmet --scene $A/DamagedHelmet/DamagedHelmet.glb --graph graph/bench_rays.ron"
  "rays_pine --scene $A/smallpine/scene.gltf --graph graph/bench_rays.ron"
  "rays_box --scene box --graph graph/bench_rays.ron"
  "primary_atrium --scene atrium --graph graph/bench_primary.ron"
  "fullrt_atrium --scene atrium --mode full-rt"
  "hybrid_default --mode hybrid"
  "hybrid_moving --scene atrium-moving --mode hybrid"
)
mkdir -p /tmp/images
for v in main "$@"; do
  for c in "${cases[@]}"; do
    name=${c%% *}; args=${c#* }
    (cd /tmp/diag_trees/$v && timeout 600 $RG render $args --backend compute --width 320 --height 180 \
      --frames 1 --out /tmp/images/${v}_$name.png > /tmp/images/${v}_$name.log 2>&1) || tail -2 /tmp/images/${v}_$name.log
    if [ $v != main ]; then
      if cmp -s /tmp/images/main_$name.png /tmp/images/${v}_$name.png; then echo "$v $name same"; else echo "$v $name DIFFERENT"; fi
    fi
  done
done
