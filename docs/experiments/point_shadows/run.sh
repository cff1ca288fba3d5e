#!/bin/bash
# Raster point-light shadows (cube maps) on the GPU machine, one release binary
# (.gpu/raygraph.gz), run in the checkout (its graph, layers and shaders): `render --mode raster
# --frames 60` at 2560x1440 on `compute` of atrium-lights (1,024 point lights: the first two have
# cube maps, twelve face passes), of the same duplicated 2x2x2 with unique triangles (8x the
# triangles: how a cube map's cost grows with the scene) and of the plain atrium (a sun: the
# face passes are not recorded), each twice in one session. Per-pass tables in
# $OUT/point_shadows.tgz; the passes' rows printed last.
set -u
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
gunzip -f .gpu/raygraph.gz; chmod +x .gpu/raygraph
ROOT=$PWD; RG=$ROOT/.gpu/raygraph; OUT=${OUT:-/tmp/out}; mkdir -p $OUT/r
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
run() { # name, then render's arguments
  local name=$1; shift
  local log=$OUT/r/${name}_$SECONDS.log
  timeout 150 $RG render --mode raster --backend compute --width 2560 --height 1440 --frames 60 --out $OUT/r/x.png "$@" > $log 2>&1 || tail -3 $log
  echo "== $name ($*)"; grep -E "^(adapter|shadow_map/|forward/|tonemap/|total|frame wall|outside)" $log
}
for round in 1 2; do
  run atrium_lights --scene atrium-lights
  run atrium_lights_dup2 --scene atrium-lights --duplicate 2 --no-dedup
  run atrium --scene atrium
done
rm -f $OUT/r/x.png
cd $OUT && tar czf point_shadows.tgz r 2>/dev/null; rm -rf r
