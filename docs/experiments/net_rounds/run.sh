#!/bin/bash
# The AO net's points a round at a time (ao_lane.wgsl at 737b877) against R2, on the GPU machine;
# one release binary (.gpu/raygraph.xz), each variant's `shaders/`, `layers/` and `graph/` in a
# folder of its own, read from there: `r2` this checkout's files (.gpu/r2.tgz), `net` the same
# with the AO layers' `sampling` default "net" (.gpu/net.tgz). `bench rays --frames 10`: Table 3
# (both back-ends), the helmet, the pine and helmet_5x5x5 (1.93M triangles) at their cameras and
# at 2%, 5% and 10% of the frame (both back-ends), each variant once; then the helmet and
# helmet_5x5x5 at 2% with the four-lane schedule (`--use-layer rt_ao=rt_ao_four_lanes`,
# compute), which tells the spread schedule's part in the net's loss on frames a few percent
# covered; then `raygraph selftest` with net. Results in $OUT/net_rounds.tgz.
set -u
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
xz -dc .gpu/raygraph.xz > .gpu/raygraph; chmod +x .gpu/raygraph
RG=$PWD/.gpu/raygraph; ROOT=$PWD; OUT=${OUT:-/tmp/out}; mkdir -p $OUT/r
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
for v in r2 net; do mkdir -p /tmp/v/$v && tar xzf .gpu/$v.tgz -C /tmp/v/$v; done
(cd /tmp/v/net && $RG scene export $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb /tmp/helmet_5x5x5.glb --duplicate 5 --no-dedup > /dev/null)
REAL="--scenes $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb,$ROOT/assets/gltf/smallpine/scene.gltf,/tmp/helmet_5x5x5.glb --coverage 0.02,0.05,0.1"
SPARSE="--scenes $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb,/tmp/helmet_5x5x5.glb --coverage 0.02 --backend compute --use-layer rt_ao=rt_ao_four_lanes"
for run in table3:r2 table3:net real:r2 real:net four:r2 four:net; do
  IFS=: read what variant <<< "$run"; name=${what}_${variant}
  args=""; [ "$what" = real ] && args="$REAL"; [ "$what" = four ] && args="$SPARSE"
  if [ $SECONDS -gt ${DEADLINE:-480} ]; then echo "deadline: $name skipped"; continue; fi
  (cd /tmp/v/$variant && timeout 200 $RG bench rays $args --frames 10 --out $OUT/r/$name > $OUT/r/$name.log 2>&1) || tail -2 $OUT/r/$name.log
  echo "== $name ($SECONDS s)"; grep -E "^\| " $OUT/r/$name/rays.md | grep -v -- "---" | grep -v " test |" | cut -d'|' -f2,3,5,6 | sed 's|/root/[^ ]*/||'
done
if [ $SECONDS -lt ${DEADLINE:-480} ]; then
  (cd /tmp/v/net && timeout 90 $RG selftest > $OUT/r/selftest.log 2>&1; echo "selftest exit $?"; tail -6 $OUT/r/selftest.log)
fi
cd $OUT && tar czf net_rounds.tgz r && rm -rf r
