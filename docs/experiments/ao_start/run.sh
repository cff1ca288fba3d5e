#!/bin/bash
# AO rays started below the root (trace_start_within, shaders/trace/compute.wgsl): shader-only
# variants side by side, one binary (the release binary reads `shaders/`, `layers/` and
# `graph/` from the folder it runs in), one session. Variants, each a folder prepared under
# .gpu/ before the call: v_base (the shaders before the change), v_k1, v_k4 (the default) and
# v_k8 (TRACE_START_NODES = 1, 4, 8: how many nodes the rays of a lane start at). `bench rays
# --scenes atrium,HELMET,PINE --coverage 0.02,0.05 --frames 10 --backend compute` in each, then
# the driver (`--backend rt-pipeline`, v_base) once, then the base and the default again.
# Results under $OUT (results.tgz); the rows printed last. (Since a0cf822 the shipped start is
# written for one node: TRACE_START_NODES is gone, docs/experiments/start_one_node/run.sh.)
#   `run.sh after`: from the checkout (its shaders: the change, one start node), Table 3
#   (`bench rays --frames 10`) and the 1.93M-triangle file (the helmet exported 5x5x5 without
#   instancing) by coverage, both back-ends.
#   `run.sh gated`: from the checkout, after the start below the root was turned off for scenes
#   of fewer than 1024 triangles (the box's AO pass had lost 67% with it): Table 3 and the two
#   real assets by coverage, `compute` only.
#   `run.sh k2`: two start nodes a lane (v_k2: the checkout's shaders with TRACE_START_NODES = 2)
#   against one (v_k1: the checkout's), alternating, `compute`, the three scenes by coverage and
#   the box.
set -u
PART=${1:-variants}
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
gunzip -f .gpu/raygraph.gz && chmod +x .gpu/raygraph
RG=$PWD/.gpu/raygraph; ROOT=$PWD
OUT=${OUT:-/tmp/out}; mkdir -p $OUT/r
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv,noheader
S=atrium,$ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb,$ROOT/assets/gltf/smallpine/scene.gltf
b() { local name=$1 dir=$2; shift 2
  if [ $SECONDS -gt 500 ]; then echo "skipped: $name"; return; fi
  (cd $ROOT/.gpu/$dir && timeout 150 $RG bench rays --scenes $S --coverage 0.02,0.05 --frames 10 "$@" --out $OUT/r/$name > $OUT/r/$name.log 2>&1) || tail -2 $OUT/r/$name.log; }
if [ "$PART" = k2 ]; then
  S=box,$S
  b k1 v_k1 --backend compute; b k2 v_k2 --backend compute; b k1_2 v_k1 --backend compute; b k2_2 v_k2 --backend compute
elif [ "$PART" = gated ]; then
  (cd $ROOT && timeout 200 $RG bench rays --frames 10 --backend compute --out $OUT/r/t3 > $OUT/r/t3.log 2>&1) || tail -2 $OUT/r/t3.log
  (cd $ROOT && timeout 200 $RG bench rays --scenes ${S#atrium,} --coverage 0.02,0.05 --frames 10 --backend compute --out $OUT/r/real > $OUT/r/real.log 2>&1) || tail -2 $OUT/r/real.log
elif [ "$PART" = after ]; then
  (cd $ROOT && timeout 200 $RG bench rays --frames 10 --out $OUT/r/t3 > $OUT/r/t3.log 2>&1) || tail -2 $OUT/r/t3.log
  (cd $ROOT && $RG scene export assets/gltf/DamagedHelmet/DamagedHelmet.glb /tmp/helmet_5x5x5.glb --duplicate 5 --no-dedup > /dev/null)
  (cd $ROOT && timeout 200 $RG bench rays --scenes /tmp/helmet_5x5x5.glb --coverage 0.02,0.05,0.1 --frames 10 --out $OUT/r/file > $OUT/r/file.log 2>&1) || tail -2 $OUT/r/file.log
else
b base v_base --backend compute
b k4 v_k4 --backend compute
b k1 v_k1 --backend compute
b k8 v_k8 --backend compute
b driver v_base --backend rt-pipeline
b base_2 v_base --backend compute
b k4_2 v_k4 --backend compute
fi
cd $OUT && tar czf results.tgz r
for d in r/*/; do n=$(basename $d); echo "== $n"
  grep -E "^\| " $d/rays.md | grep -vE -- "---|^\| test" | cut -d'|' -f2,5,8 | sed -e 's#/[^ ]*/##'
  grep -E ",ao/ao," $d/rays_passes.csv | sed -e 's#^/[^,]*/##' | cut -d, -f1,4 | tr '\n' ' '; echo
done
rm -rf r
