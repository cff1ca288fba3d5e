#!/bin/bash
# Diagnostic, not a change: AO rays in an order that makes a subgroup's rays of one round point
# the same way, on the GPU machine. Both patches put a per-pixel XOR-scrambled 2D Sobol net of
# 64 points in place of R2 rotated per pixel: sobol_index.patch traces point i as ray i,
# sobol_cells.patch the point in cell i of the 8x8 grid in Morton order (the same 64 rays a
# pixel, so the same AO bit for bit with Table 3's 64 rays; only which lane traces which ray in
# which round differs). Against main's files; one release binary (.gpu/raygraph.xz),
# each variant's `shaders/`, `layers/` and `graph/` in a folder of its own (.gpu/main.tgz, then
# patched), read from there. `bench rays --frames 10`, compute only: Table 3's rows, main,
# index and cells alternating twice; then the helmet, the pine and helmet_5x5x5 (1.93M
# triangles) at their cameras and at 2%, 5% and 10% of the frame, index and cells once each.
# (The first run's patch, which found each cell's point by a search, is in git at 44c6ef5.) Results in $OUT/cell_order.tgz; the
# tables printed (medians of 10 frames after the settling warm-up).
set -u
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
xz -dc .gpu/raygraph.xz > .gpu/raygraph; chmod +x .gpu/raygraph
RG=$PWD/.gpu/raygraph; ROOT=$PWD; OUT=${OUT:-/tmp/out}; mkdir -p $OUT/r
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
mkdir -p /tmp/v/main && tar xzf .gpu/main.tgz -C /tmp/v/main
for v in index cells; do
  cp -r /tmp/v/main /tmp/v/$v
  (cd /tmp/v/$v && patch -s -p0 < $ROOT/docs/experiments/cell_order/sobol_$v.patch) || { echo "sobol_$v.patch did not apply"; exit 1; }
done
(cd /tmp/v/main && $RG scene export $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb /tmp/helmet_5x5x5.glb --duplicate 5 --no-dedup > /dev/null)
REAL="--scenes $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb,$ROOT/assets/gltf/smallpine/scene.gltf,/tmp/helmet_5x5x5.glb --coverage 0.02,0.05,0.1"
for run in table3:main:1 table3:index:1 table3:cells:1 table3:main:2 table3:index:2 table3:cells:2 real:index:1 real:cells:1; do
  IFS=: read what variant round <<< "$run"; name=${what}_${variant}_$round
  args="--backend compute"; [ "$what" = real ] && args="$args $REAL"
  if [ $SECONDS -gt ${DEADLINE:-500} ]; then echo "deadline: $name skipped"; continue; fi
  (cd /tmp/v/$variant && timeout 200 $RG bench rays $args --frames 10 --out $OUT/r/$name > $OUT/r/$name.log 2>&1) || tail -2 $OUT/r/$name.log
  echo "== $name ($SECONDS s)"; grep -E "^\| " $OUT/r/$name/rays.md | grep -v -- "---" | grep -v " test |" | cut -d'|' -f2,4,5,14
done
cd $OUT && tar czf cell_order.tgz r && rm -rf r
