#!/bin/bash
# AO schedules against each other, one binary, one run (.gpu/raygraph): `bench rays --frames
# 10` on both back-ends with `--use-layer rt_ao=V` for each V of $VARIANTS (default: the
# four-lane schedule, then rt_ao itself, which spreads a pixel's rays over more lanes where few
# pixels have rays; before rt_ao became that, the spread schedule was rt_ao_spread).
# `run.sh real`: the helmet, the pine and helmet_5x5x5 (the helmet copied 5 times per axis
# without instancing, 1.93M triangles) at 2%, 5% and 10% of the frame;
# `run.sh table3`: the built-in rows (Table 3). From an empty folder (the binary's built-in
# graphs, layers and shaders). Prints the tables.
set -u
WHAT=${1:-real}
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
gunzip -f .gpu/raygraph.gz; chmod +x .gpu/raygraph
RG=$PWD/.gpu/raygraph; ROOT=$PWD; OUT=${OUT:-/tmp/out}; mkdir -p $OUT/r /tmp/empty
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
ARGS=""
if [ "$WHAT" = real ]; then
  (cd /tmp/empty && $RG scene export $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb /tmp/helmet_5x5x5.glb --duplicate 5 --no-dedup > /dev/null)
  ARGS="--scenes $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb,$ROOT/assets/gltf/smallpine/scene.gltf,/tmp/helmet_5x5x5.glb --coverage 0.02,0.05,0.1"
fi
for variant in ${VARIANTS:-rt_ao_four_lanes rt_ao}; do
  if [ $SECONDS -gt ${DEADLINE:-480} ]; then echo "deadline: $variant skipped"; break; fi
  (cd /tmp/empty && timeout 280 $RG bench rays $ARGS --use-layer rt_ao=$variant --frames 10 --out $OUT/r/${WHAT}_$variant > $OUT/r/${WHAT}_$variant.log 2>&1) || tail -2 $OUT/r/${WHAT}_$variant.log
done
cd $OUT && tar czf ${WHAT}.tgz r
for variant in ${VARIANTS:-rt_ao_four_lanes rt_ao}; do
  [ -f r/${WHAT}_$variant/rays.md ] && { echo "== $variant"; grep -E "^\| " r/${WHAT}_$variant/rays.md | grep -v -- "---" | cut -d'|' -f2-5,7,8; }
done
rm -rf r
