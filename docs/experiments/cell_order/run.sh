#!/bin/bash
# Diagnostic, not a change: AO rays in an order that makes a subgroup's rays of one round point
# the same way (cell_order.patch: ray i of a pixel's 64 takes the point of a per-pixel
# XOR-scrambled 2D Sobol net in cell i of the 8x8 grid in Morton order, in place of R2 rotated
# per pixel), against main's files, on the GPU machine; one release binary (.gpu/raygraph.xz),
# each variant's `shaders/`, `layers/` and `graph/` in a folder of its own (.gpu/main.tgz, then
# patched), read from there. `bench rays --frames 10`, compute only: Table 3's rows, main and
# cells alternating twice; then the helmet, the pine and helmet_5x5x5 (1.93M triangles) at their
# cameras and at 2%, 5% and 10% of the frame, once each. Results in $OUT/cell_order.tgz; the
# tables printed (medians of 10 frames after the settling warm-up).
set -u
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
xz -dc .gpu/raygraph.xz > .gpu/raygraph; chmod +x .gpu/raygraph
RG=$PWD/.gpu/raygraph; ROOT=$PWD; OUT=${OUT:-/tmp/out}; mkdir -p $OUT/r
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
mkdir -p /tmp/v/main && tar xzf .gpu/main.tgz -C /tmp/v/main && cp -r /tmp/v/main /tmp/v/cells
(cd /tmp/v/cells && patch -s -p0 < $ROOT/docs/experiments/cell_order/cell_order.patch) || { echo "cell_order.patch did not apply"; exit 1; }
(cd /tmp/v/main && $RG scene export $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb /tmp/helmet_5x5x5.glb --duplicate 5 --no-dedup > /dev/null)
REAL="--scenes $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb,$ROOT/assets/gltf/smallpine/scene.gltf,/tmp/helmet_5x5x5.glb --coverage 0.02,0.05,0.1"
for run in table3:main:1 table3:cells:1 table3:main:2 table3:cells:2 real:main:1 real:cells:1; do
  IFS=: read what variant round <<< "$run"; name=${what}_${variant}_$round
  args="--backend compute"; [ "$what" = real ] && args="$args $REAL"
  if [ $SECONDS -gt ${DEADLINE:-500} ]; then echo "deadline: $name skipped"; continue; fi
  (cd /tmp/v/$variant && timeout 200 $RG bench rays $args --frames 10 --out $OUT/r/$name > $OUT/r/$name.log 2>&1) || tail -2 $OUT/r/$name.log
  echo "== $name ($SECONDS s)"; grep -E "^\| " $OUT/r/$name/rays.md | grep -v -- "---" | grep -v " test |" | cut -d'|' -f2,4,5,14
done
cd $OUT && tar czf cell_order.tgz r && rm -rf r
