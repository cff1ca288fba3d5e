#!/bin/bash
# A lane's AO rays as one batch in one traversal loop (trace/ray_batch.wgsl) against the same
# rays one after another (the shaders of bcf828d), on the GPU machine; one release binary
# (.gpu/raygraph.xz, which embeds the batch), each variant's `shaders/`, `layers/` and `graph/`
# unpacked into a folder of its own from .gpu/VARIANT.tgz and read from there:
#   before       the shaders of bcf828d (rays one by one)
#   batch        this checkout's (one loop, a node or a leaf per iteration)
#   while_while  batch with docs/experiments/ray_batch/while_while.patch applied (interior
#                nodes in an inner loop until a leaf)
# `run.sh table3`: `bench rays --frames 10` (the built-in rows), before, batch, while_while,
# alternating, twice. `run.sh real`: the helmet, the pine and helmet_5x5x5 (1.93M triangles)
# at their cameras and at 2%, 5% and 10% of the frame, before then batch; then `raygraph
# selftest` and the atrium's frames (`render --mode M --scene atrium --width 2560 --height 1440
# --frames 60`, M = hybrid, full-rt) with each. Logs and results in $OUT/WHAT.tgz; the tables
# printed (medians of 10 frames after the settling warm-up).
set -u
WHAT=${1:-table3}
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
xz -dc .gpu/raygraph.xz > .gpu/raygraph; chmod +x .gpu/raygraph
RG=$PWD/.gpu/raygraph; ROOT=$PWD; OUT=${OUT:-/tmp/out}; mkdir -p $OUT/r
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
for v in before batch; do mkdir -p /tmp/v/$v && tar xzf .gpu/$v.tgz -C /tmp/v/$v; done
cp -r /tmp/v/batch /tmp/v/while_while
(cd /tmp/v/while_while && patch -p0 < $ROOT/docs/experiments/ray_batch/while_while.patch) || { echo "while_while.patch did not apply"; exit 1; }
ARGS=""; RUNS="before:1 batch:1 while_while:1 before:2 batch:2 while_while:2"
if [ "$WHAT" = real ]; then
  (cd /tmp/v/batch && $RG scene export $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb /tmp/helmet_5x5x5.glb --duplicate 5 --no-dedup > /dev/null)
  ARGS="--scenes $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb,$ROOT/assets/gltf/smallpine/scene.gltf,/tmp/helmet_5x5x5.glb --coverage 0.02,0.05,0.1"
  RUNS="before:1 batch:1"
fi
for run in $RUNS; do
  variant=${run%:*}; name=${WHAT}_${variant}_${run#*:}
  if [ $SECONDS -gt ${DEADLINE:-500} ]; then echo "deadline: $name skipped"; continue; fi
  (cd /tmp/v/$variant && timeout 280 $RG bench rays $ARGS --frames 10 --out $OUT/r/$name > $OUT/r/$name.log 2>&1) || tail -2 $OUT/r/$name.log
  echo "== $name ($SECONDS s)"; grep -E "^\| " $OUT/r/$name/rays.md | grep -v -- "---" | grep -v "ray-query" | cut -d'|' -f2-5,8,14
done
if [ "$WHAT" = real ]; then
  (cd /tmp/v/batch && timeout 120 $RG selftest > $OUT/r/selftest.log 2>&1; echo "selftest exit $?"; tail -3 $OUT/r/selftest.log)
  for mode in hybrid full-rt; do
    for variant in before batch; do
      if [ $SECONDS -gt ${DEADLINE:-500} ]; then echo "deadline: $mode $variant skipped"; continue; fi
      log=$OUT/r/frame_${mode}_$variant.log
      (cd /tmp/v/$variant && timeout 60 $RG render --mode $mode --scene atrium --backend compute \
        --width 2560 --height 1440 --frames 60 --out /tmp/x.png > $log 2>&1) || tail -2 $log
      echo "$mode $variant | $(grep -E '^total' $log | awk '{print "gpu", $3}') | $(grep -E '^frame wall' $log | sed 's/.*: //')"
    done
  done
fi
cd $OUT && tar czf $WHAT.tgz r && rm -rf r
