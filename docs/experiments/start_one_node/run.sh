#!/bin/bash
# The start below the root written for one node (trace_start_within in
# shaders/trace/compute.wgsl: one node and TRACE_START_NONE instead of an array of
# TRACE_START_NODES = 1 with a count), against the general code it replaces: the same AO images
# on lavapipe (EXRs byte-identical: atrium, default, helmet, pine, organic). Two release
# binaries in one call, .gpu/raygraph-before (a26bb13) and .gpu/raygraph (the change), each
# from the checkout (the binaries embed their shaders): Table 3 (`bench rays --frames 10
# --backend compute`) and the real assets by coverage (`--scenes HELMET,PINE --coverage
# 0.02,0.05`), before, after, before, after. Results in $OUT/results.tgz; the rows printed last.
set -u
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
gunzip -f .gpu/*.gz && chmod +x .gpu/raygraph*
ROOT=$PWD; OUT=${OUT:-/tmp/out}; mkdir -p $OUT/r
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
S=$ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb,$ROOT/assets/gltf/smallpine/scene.gltf
# An empty folder: the binary's built-in graphs, layers and shaders.
mkdir -p /tmp/empty
b() { local name=$1 bin=$2; shift 2
  if [ $SECONDS -gt 500 ]; then echo "skipped: $name"; return; fi
  (cd /tmp/empty && timeout 200 $bin bench rays --frames 10 --backend compute "$@" --out $OUT/r/$name > $OUT/r/$name.log 2>&1) || tail -2 $OUT/r/$name.log; }
for k in 1 2; do
  b t3_before_$k $ROOT/.gpu/raygraph-before
  b t3_after_$k $ROOT/.gpu/raygraph
  b real_before_$k $ROOT/.gpu/raygraph-before --scenes $S --coverage 0.02,0.05
  b real_after_$k $ROOT/.gpu/raygraph --scenes $S --coverage 0.02,0.05
done
cd $OUT && tar czf results.tgz r
for d in r/*/; do n=$(basename $d); echo "== $n"
  grep -E "^\| " $d/rays.md | grep -vE -- "---|^\| test" | cut -d'|' -f2,5,8 | sed -e 's#/[^ ]*/##' | tr '\n' ' '; echo
done
rm -rf r
