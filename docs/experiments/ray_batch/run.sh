#!/bin/bash
# A lane's AO rays as one batch in one traversal loop (trace/ray_batch.wgsl) against the same
# rays one after another, on the GPU machine; one release binary (.gpu/raygraph.xz), each
# variant's `shaders/`, `layers/` and `graph/` in a folder of its own, read from there:
#   before       the files of bcf828d (.gpu/before.tgz): rays one by one, before the batch
#   batch        this checkout's (.gpu/batch.tgz): one loop, a node or a leaf per iteration,
#                every branch to the iteration's end
#   one_by_one   batch with trace/ray_batch_loop.wgsl (the other back-ends' batch: rays one
#                after another) in place of trace/ray_batch.wgsl
#   blas_fallthrough  batch with blas_fallthrough.patch (trace_blas's interior step without
#                `continue`: every branch to the loop's end)
# (The second run's while_while and flat_ray patches are in git at cb45638, with this script as
# it was.)
# `run.sh table3 V1,V2,...`: `bench rays --frames 10` (the built-in rows, compute only), the
# variants alternating, twice. `run.sh real V1,V2`: the helmet, the pine and helmet_5x5x5
# (1.93M triangles) at their cameras and at 2%, 5% and 10% of the frame, both back-ends; then
# `raygraph selftest` and the atrium's frames (`render --mode M --scene atrium --width 2560
# --height 1440 --frames 60`, M = hybrid, full-rt) with each. Logs and results in
# $OUT/WHAT.tgz; the tables printed (medians of 10 frames after the settling warm-up).
set -u
WHAT=${1:-table3}; VARIANTS=${2:-before,batch}
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
xz -dc .gpu/raygraph.xz > .gpu/raygraph; chmod +x .gpu/raygraph
RG=$PWD/.gpu/raygraph; ROOT=$PWD; OUT=${OUT:-/tmp/out}; mkdir -p $OUT/r
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
for v in before batch; do mkdir -p /tmp/v/$v && tar xzf .gpu/$v.tgz -C /tmp/v/$v; done
cp -r /tmp/v/batch /tmp/v/one_by_one
cp /tmp/v/batch/shaders/trace/ray_batch_loop.wgsl /tmp/v/one_by_one/shaders/trace/ray_batch.wgsl
for p in blas_fallthrough; do
  cp -r /tmp/v/batch /tmp/v/$p
  (cd /tmp/v/$p && patch -s -p0 < $ROOT/docs/experiments/ray_batch/$p.patch) || { echo "$p.patch did not apply"; exit 1; }
done
ARGS="--backend compute"; ROUNDS="1 2"
if [ "$WHAT" = real ]; then
  (cd /tmp/v/batch && $RG scene export $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb /tmp/helmet_5x5x5.glb --duplicate 5 --no-dedup > /dev/null)
  ARGS="--scenes $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb,$ROOT/assets/gltf/smallpine/scene.gltf,/tmp/helmet_5x5x5.glb --coverage 0.02,0.05,0.1"
  ROUNDS="1"
fi
for round in $ROUNDS; do
  for variant in ${VARIANTS//,/ }; do
    name=${WHAT}_${variant}_$round
    if [ $SECONDS -gt ${DEADLINE:-500} ]; then echo "deadline: $name skipped"; continue; fi
    (cd /tmp/v/$variant && timeout 280 $RG bench rays $ARGS --frames 10 --out $OUT/r/$name > $OUT/r/$name.log 2>&1) || tail -2 $OUT/r/$name.log
    echo "== $name ($SECONDS s)"; grep -E "^\| " $OUT/r/$name/rays.md | grep -v -- "---" | grep -v "ray-query" | cut -d'|' -f2-5,8,14
  done
done
if [ "$WHAT" = real ]; then
  (cd /tmp/v/batch && timeout 120 $RG selftest > $OUT/r/selftest.log 2>&1; echo "selftest exit $?"; tail -3 $OUT/r/selftest.log)
  for mode in hybrid full-rt; do
    for variant in ${VARIANTS//,/ }; do
      if [ $SECONDS -gt ${DEADLINE:-500} ]; then echo "deadline: $mode $variant skipped"; continue; fi
      log=$OUT/r/frame_${mode}_$variant.log
      (cd /tmp/v/$variant && timeout 60 $RG render --mode $mode --scene atrium --backend compute \
        --width 2560 --height 1440 --frames 60 --out /tmp/x.png > $log 2>&1) || tail -2 $log
      echo "$mode $variant | $(grep -E '^total' $log | awk '{print "gpu", $3}') | $(grep -E '^frame wall' $log | sed 's/.*: //')"
    done
  done
fi
cd $OUT && tar czf $WHAT.tgz r && rm -rf r
