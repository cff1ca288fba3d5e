#!/bin/bash
# The AO layers' default sampling, "net" (rays in cell order), against "r2" (the default before),
# on the GPU machine; one release binary (.gpu/raygraph.xz), each variant's `shaders/`,
# `layers/` and `graph/` in a folder of its own, read from there: `r2` the files of 148a76a
# (.gpu/r2.tgz), `net` this checkout's (.gpu/net.tgz). `bench rays --frames 10`: Table 3's rows
# (both back-ends), r2 and net alternating twice; the helmet, the pine and helmet_5x5x5 (1.93M
# triangles) at their cameras and at 2%, 5% and 10% of the frame, both back-ends, once each; the
# atrium's frames (`render --mode M --scene atrium --backend compute --width 2560 --height 1440
# --frames 60`, M = hybrid, full-rt) with each; `raygraph selftest` with net. Results in
# $OUT/ao_net.tgz; the tables printed (medians of 10 frames after the settling warm-up).
set -u
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
xz -dc .gpu/raygraph.xz > .gpu/raygraph; chmod +x .gpu/raygraph
RG=$PWD/.gpu/raygraph; ROOT=$PWD; OUT=${OUT:-/tmp/out}; mkdir -p $OUT/r
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
for v in r2 net; do mkdir -p /tmp/v/$v && tar xzf .gpu/$v.tgz -C /tmp/v/$v; done
(cd /tmp/v/net && $RG scene export $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb /tmp/helmet_5x5x5.glb --duplicate 5 --no-dedup > /dev/null)
REAL="--scenes $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb,$ROOT/assets/gltf/smallpine/scene.gltf,/tmp/helmet_5x5x5.glb --coverage 0.02,0.05,0.1"
for run in table3:r2:1 table3:net:1 table3:r2:2 table3:net:2 real:r2:1 real:net:1; do
  IFS=: read what variant round <<< "$run"; name=${what}_${variant}_$round
  args=""; [ "$what" = real ] && args="$REAL"
  if [ $SECONDS -gt ${DEADLINE:-400} ]; then echo "deadline: $name skipped"; continue; fi
  (cd /tmp/v/$variant && timeout 200 $RG bench rays $args --frames 10 --out $OUT/r/$name > $OUT/r/$name.log 2>&1) || tail -2 $OUT/r/$name.log
  echo "== $name ($SECONDS s)"; grep -E "^\| " $OUT/r/$name/rays.md | grep -v -- "---" | grep -v " test |" | cut -d'|' -f2,3,5,6
done
for mode in hybrid full-rt; do
  for variant in r2 net; do
    if [ $SECONDS -gt ${DEADLINE:-400} ]; then echo "deadline: $mode $variant skipped"; continue; fi
    log=$OUT/r/frame_${mode}_$variant.log
    (cd /tmp/v/$variant && timeout 60 $RG render --mode $mode --scene atrium --backend compute \
      --width 2560 --height 1440 --frames 60 --out /tmp/x.png > $log 2>&1) || tail -2 $log
    echo "$mode $variant | $(grep -E '^total' $log | awk '{print "gpu", $3}') | $(grep -E '^frame wall' $log | sed 's/.*: //')"
  done
done
(cd /tmp/v/net && timeout 150 $RG selftest > $OUT/r/selftest.log 2>&1; echo "selftest exit $?"; tail -12 $OUT/r/selftest.log)
cd $OUT && tar czf ao_net.tgz r && rm -rf r
