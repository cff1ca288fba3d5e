#!/bin/bash
# rt_ao's two schedules picked from the frame before (`runs_when`), against the four-lane
# schedule, one release binary (.gpu/raygraph.xz), built-in files (an empty folder), on the GPU
# machine. `run.sh table3`: `bench rays --frames 10` (the built-in rows) with `--use-layer
# rt_ao=V` for V = rt_ao_four_lanes, rt_ao (spread below an eighth of the frame covered),
# rt_ao_quarter (the same layer spreading below a quarter, written from layers/rt_ao.ron
# here), alternating, twice. `run.sh real`: the helmet, the pine and helmet_5x5x5 (the helmet
# copied 5 times per axis without instancing, 1.93M triangles) at their cameras and at 2%, 5%
# and 10% of the frame, rt_ao_four_lanes then rt_ao; then the frame's CPU time outside the
# passes, `render --graph G --scene atrium --backend compute --width 2560 --height 1440
# --frames 60` for G = hybrid, full_rt, ao with rt_ao and rt_ao_four_lanes. Logs and results
# in $OUT/WHAT.tgz; the tables printed (medians of 10 frames after the settling warm-up).
set -u
WHAT=${1:-table3}
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
xz -dc .gpu/raygraph.xz > .gpu/raygraph; chmod +x .gpu/raygraph
RG=$PWD/.gpu/raygraph; ROOT=$PWD; OUT=${OUT:-/tmp/out}; mkdir -p $OUT/r /tmp/empty/layers
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
sed 's/fraction: 0.125/fraction: 0.25/' $ROOT/layers/rt_ao.ron > /tmp/empty/layers/rt_ao_quarter.ron
ARGS=""; RUNS="rt_ao_four_lanes:1 rt_ao:1 rt_ao_quarter:1 rt_ao_four_lanes:2 rt_ao:2 rt_ao_quarter:2"
if [ "$WHAT" = real ]; then
  (cd /tmp/empty && $RG scene export $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb /tmp/helmet_5x5x5.glb --duplicate 5 --no-dedup > /dev/null)
  ARGS="--scenes $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb,$ROOT/assets/gltf/smallpine/scene.gltf,/tmp/helmet_5x5x5.glb --coverage 0.02,0.05,0.1"
  RUNS="rt_ao_four_lanes:1 rt_ao:1"
fi
for run in $RUNS; do
  variant=${run%:*}; name=${WHAT}_${variant}_${run#*:}
  if [ $SECONDS -gt ${DEADLINE:-480} ]; then echo "deadline: $name skipped"; continue; fi
  (cd /tmp/empty && timeout 280 $RG bench rays $ARGS --use-layer rt_ao=$variant --frames 10 --out $OUT/r/$name > $OUT/r/$name.log 2>&1) || tail -2 $OUT/r/$name.log
  echo "== $name ($SECONDS s)"; grep -E "^\| " $OUT/r/$name/rays.md | grep -v -- "---" | grep -v "ray-query" | cut -d'|' -f2-5,8,14
done
if [ "$WHAT" = real ]; then
  for graph in hybrid full_rt ao; do
    for variant in rt_ao rt_ao_four_lanes; do
      if [ $SECONDS -gt ${DEADLINE:-480} ]; then echo "deadline: $graph $variant skipped"; continue; fi
      log=$OUT/r/frame_${graph}_$variant.log
      (cd /tmp/empty && timeout 60 $RG render --graph graph/$graph.ron --scene atrium --backend compute --use-layer rt_ao=$variant \
        --width 2560 --height 1440 --frames 60 --out /tmp/x.png > $log 2>&1) || tail -2 $log
      echo "$graph $variant | $(grep -E '^total' $log | awk '{print "gpu", $3}') | $(grep -E '^frame wall' $log | sed 's/.*: //') | $(grep -E '^outside' $log | sed 's/.*medians): //')"
    done
  done
fi
cd $OUT && tar czf $WHAT.tgz r && rm -rf r
