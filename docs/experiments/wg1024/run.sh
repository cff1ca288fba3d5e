#!/bin/bash
# PERF.md step 37: the AO, shadow and primary tests' kernels in 1024-invocation workgroups, so
# that the driver compiles them within 64 registers a lane (variants in
# docs/experiments/live_state/variants: `wg1024`, `rows_wg1024` with `rows_at_leaf`). Made by
# `bash docs/experiments/low_coverage/pack.sh REV docs/experiments/live_state wg1024
# rows_wg1024`. First the driver's statistics of each kernel (`render --kernel-stats`), then
# `bench rays --backend compute --frames 10`: Table 3 for main, both variants and main again;
# the real assets (the helmet, the pine, at their cameras and at 2%, 5%, 10% of the frame) for
# main, `wg1024`, `rows_wg1024`. One release binary (.gpu/raygraph.xz). Results in
# $OUT/wg1024.tgz.
. docs/experiments/low_coverage/preamble.sh
for v in main wg1024 rows_wg1024; do
  for what in atrium primary; do
    graph=graph/bench_rays.ron; [ $what = primary ] && graph=graph/bench_primary.ron
    (cd /tmp/v/$v && timeout 120 $RG render --scene atrium --graph $graph --backend compute --width 320 --height 180 --frames 1 \
      --out $OUT/r/${v}_$what.png --kernel-stats $OUT/r/${v}_$what.md > $OUT/r/${v}_$what.log 2>&1) || tail -3 $OUT/r/${v}_$what.log
    echo "== $v $what"; awk '/^## /{k=$2} /Register Count/ {r=$5} /Local Memory/ {print "  " k " registers " r ", local bytes " $6 % 4294967296}' $OUT/r/${v}_$what.md
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
bench main table3; bench wg1024 table3; bench rows_wg1024 table3; bench main table3
bench main real; bench wg1024 real; bench rows_wg1024 real
cd $OUT && tar czf wg1024.tgz r && rm -rf r
