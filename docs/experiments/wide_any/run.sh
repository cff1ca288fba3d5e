#!/bin/bash
# PERF.md step 34: any-hit rays take a 4-wide step on the binary layout where both children of
# a node are hit and interior (variants/wide_any.patch: their four children loaded and tested
# in one step, the nearest visited next, the others pushed; the same images). Made by `bash
# docs/experiments/low_coverage/pack.sh 1ff4ade docs/experiments/wide_any wide_any`. Table 3
# and the real assets (the helmet, the pine, at their cameras and at 2%, 5%, 10% of the frame),
# `bench rays --backend compute --frames 10`, main, the variant, main. One release binary
# (.gpu/raygraph.xz, built from ad28fc7). Results in $OUT/wide_any.tgz.
. docs/experiments/low_coverage/preamble.sh
for name in main wide_any main; do
  for what in table3 real; do
    n=${name}_$what; [ -d $OUT/r/$n ] && n=${n}_2
    args=""; [ $what = real ] && args="$REAL"
    if [ $SECONDS -gt ${DEADLINE:-500} ]; then echo "deadline: $n skipped"; continue; fi
    (cd /tmp/v/$name && timeout 150 $RG bench rays $args --backend compute --frames 10 --out $OUT/r/$n > $OUT/r/$n.log 2>&1) || tail -2 $OUT/r/$n.log
    echo "== $n ($SECONDS s)"; grep -E "^\| " $OUT/r/$n/rays.md | grep -v -- "---" | grep -v " test |" | awk -F'|' '{print $2 "|" $5 "|" $6}' | sed 's|/[^ ]*/||'
  done
done
cd $OUT && tar czf wide_any.tgz r && rm -rf r
