#!/bin/bash
# PERF.md step 29: the BLAS child pairs with 16-bit boxes against the exact nodes, one binary,
# one run. Variants, each with its `shaders/`, `layers/` and `graph/` in a folder of its own:
# `main` (.gpu/main.tgz: the files of 1f35499, whose trace shaders bind no pairs), `exact`
# (this checkout's files with RAYGRAPH_EXACT_BOXES=1: every grid invalid, the exact loop) and
# `pairs` (this checkout's files). `bench rays --frames 10`: Table 3 for each (both back-ends);
# the real assets (the helmet, the pine, helmet_5x5x5 at their cameras and at 2%, 5%, 10% of
# the frame) for `pairs` and `exact`. Results in $OUT/quantised_pairs.tgz.
set -u
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
xz -dc .gpu/raygraph.xz > .gpu/raygraph; chmod +x .gpu/raygraph
ROOT=$PWD; OUT=${OUT:-/tmp/out}; mkdir -p $OUT/r
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
mkdir -p /tmp/v/main /tmp/v/pairs && tar xzf .gpu/main.tgz -C /tmp/v/main
cp -r shaders layers graph /tmp/v/pairs/
(cd /tmp/v/pairs && $ROOT/.gpu/raygraph scene export $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb /tmp/helmet_5x5x5.glb --duplicate 5 --no-dedup > /dev/null)
REAL="--scenes $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb,$ROOT/assets/gltf/smallpine/scene.gltf,/tmp/helmet_5x5x5.glb --coverage 0.02,0.05,0.1"
for run in table3:pairs:0 table3:exact:1 table3:main:0 real:pairs:0 real:exact:1; do
  IFS=: read what variant exact <<< "$run"; name=${what}_${variant}
  dir=/tmp/v/$variant; [ "$variant" = exact ] && dir=/tmp/v/pairs
  args=""; [ "$what" = real ] && args="$REAL"
  if [ $SECONDS -gt ${DEADLINE:-500} ]; then echo "deadline: $name skipped"; continue; fi
  (cd $dir && RAYGRAPH_EXACT_BOXES=$exact timeout 200 $ROOT/.gpu/raygraph bench rays $args --frames 10 --out $OUT/r/$name > $OUT/r/$name.log 2>&1) || tail -2 $OUT/r/$name.log
  echo "== $name ($SECONDS s)"; grep -E "^\| " $OUT/r/$name/rays.md | grep -v -- "---" | grep -v " test |" | cut -d'|' -f2,3,5,6 | sed 's|/[^ ]*/||'
done
cd $OUT && tar czf quantised_pairs.tgz r && rm -rf r
