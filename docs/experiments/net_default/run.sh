#!/bin/bash
# The AO sampler carrying two words (ao_lane.wgsl at 9303b08) with R2 and with the net, against
# main before this stop (the files of 3cdedaa), and the net on the tree of the reinsertion
# optimizer (a second binary, .gpu/reinsert.xz, where present). Each variant's `shaders/`,
# `layers/` and `graph/` in a folder of its own, read from there: `main` (.gpu/main.tgz), `r2`
# (.gpu/r2.tgz: this checkout's files), `net` (.gpu/net.tgz: the same with the AO layers'
# `sampling` default "net"). `bench rays --frames 10`: Table 3 for main, r2, net and net on the
# reinserted tree (both back-ends); the real assets (the helmet, the pine, helmet_5x5x5 at their
# cameras and at 2%, 5%, 10% of the frame, both back-ends) for the net on both trees. Results in
# $OUT/net_default.tgz.
set -u
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
xz -dc .gpu/raygraph.xz > .gpu/raygraph; chmod +x .gpu/raygraph
[ -f .gpu/reinsert.xz ] && { xz -dc .gpu/reinsert.xz > .gpu/reinsert; chmod +x .gpu/reinsert; }
ROOT=$PWD; OUT=${OUT:-/tmp/out}; mkdir -p $OUT/r
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
for v in main r2 net; do mkdir -p /tmp/v/$v && tar xzf .gpu/$v.tgz -C /tmp/v/$v; done
(cd /tmp/v/net && $ROOT/.gpu/raygraph scene export $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb /tmp/helmet_5x5x5.glb --duplicate 5 --no-dedup > /dev/null)
REAL="--scenes $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb,$ROOT/assets/gltf/smallpine/scene.gltf,/tmp/helmet_5x5x5.glb --coverage 0.02,0.05,0.1"
for run in table3:main:raygraph table3:r2:raygraph table3:net:raygraph table3:net:reinsert real:net:raygraph real:net:reinsert; do
  IFS=: read what variant binary <<< "$run"; name=${what}_${variant}_$binary
  [ -x .gpu/$binary ] || { echo "no binary: $name skipped"; continue; }
  args=""; [ "$what" = real ] && args="$REAL"
  if [ $SECONDS -gt ${DEADLINE:-480} ]; then echo "deadline: $name skipped"; continue; fi
  (cd /tmp/v/$variant && timeout 200 $ROOT/.gpu/$binary bench rays $args --frames 10 --out $OUT/r/$name > $OUT/r/$name.log 2>&1) || tail -2 $OUT/r/$name.log
  echo "== $name ($SECONDS s)"; grep -E "^\| " $OUT/r/$name/rays.md | grep -v -- "---" | grep -v " test |" | cut -d'|' -f2,3,5,6 | sed 's|/[^ ]*/||'
done
cd $OUT && tar czf net_default.tgz r && rm -rf r
