#!/bin/bash
# PERF.md step 38: one traversal in each trace kernel, the merged instance's BLAS loop
# (docs/experiments/live_state/variants/merged_only.patch; diagnostic, right for merged scenes
# only, which every scene here is). Made by `bash docs/experiments/low_coverage/pack.sh REV
# docs/experiments/live_state merged_only`. The driver's statistics of each kernel
# (`render --kernel-stats`: the atrium's scene workload, the primary tests' kernel, the pine's
# scene workload), then `bench rays --backend compute --frames 10`, Table 3 and the real assets
# (the helmet, the pine, at their cameras and at 2%, 5%, 10% of the frame): main, merged_only,
# main. One release binary (.gpu/raygraph.xz). Results in $OUT/merged_only.tgz.
. docs/experiments/low_coverage/preamble.sh
for v in main merged_only; do
  for what in atrium primary pine; do
    case $what in
      atrium) args="--scene atrium --graph graph/bench_rays.ron" ;;
      primary) args="--scene atrium --graph graph/bench_primary.ron" ;;
      pine) args="--scene $ROOT/assets/gltf/smallpine/scene.gltf --graph graph/bench_rays.ron" ;;
    esac
    (cd /tmp/v/$v && timeout 120 $RG render $args --backend compute --width 320 --height 180 --frames 1 \
      --out $OUT/r/${v}_$what.png --kernel-stats $OUT/r/${v}_$what.md > $OUT/r/${v}_$what.log 2>&1) || tail -3 $OUT/r/${v}_$what.log
    echo "== $v $what"; awk '/^## /{k=$2} /Register Count/ {r=$5} /Binary Size/ {b=$5} /Local Memory/ {print "  " k " registers " r ", binary " b ", local bytes " $6 % 4294967296}' $OUT/r/${v}_$what.md
  done
done
bench() { # bench NAME WHAT
  local name=$1 what=$2 n=${1}_$2 args=""
  [ -d $OUT/r/$n ] && n=${n}_2
  [ $what = real ] && args="$REAL"
  if [ $SECONDS -gt ${DEADLINE:-530} ]; then echo "deadline: $n skipped"; return; fi
  (cd /tmp/v/$name && timeout 150 $RG bench rays $args --backend compute --frames 10 --out $OUT/r/$n > $OUT/r/$n.log 2>&1) || tail -2 $OUT/r/$n.log
  echo "== $n ($SECONDS s)"; grep -E "^\| " $OUT/r/$n/rays.md | grep -v -- "---" | grep -v " test |" | awk -F'|' '{print $2 "|" $5 "|" $6}' | sed 's|/[^ ]*/||'
}
for v in main merged_only main; do bench $v table3; bench $v real; done
cd $OUT && tar czf merged_only.tgz r && rm -rf r
