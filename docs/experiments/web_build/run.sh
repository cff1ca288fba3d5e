#!/bin/bash
# The H100 run for the web build (issue: raygraph in the browser): native behaviour and Table 3
# unchanged by it. Two binaries in one call, alternating: .gpu/raygraph-old (71e8dcd, before the
# web build) and .gpu/raygraph (the web build's commit): Table 3 (`bench rays`) twice each, and
# the three modes on box and atrium rendered by both and compared byte for byte. Results land in
# $OUT/results.tgz; the short table is printed last.
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
OLD=$PWD/.gpu/raygraph-old; NEW=$PWD/.gpu/raygraph
mkdir -p $OUT/img
$NEW bench rays --scenes box --backend compute --frames 5 --out /tmp/warm 2>&1 | grep -iE "adapter" | head -1
t3() { grep -E "^\| " $1/rays.md | grep -v -- "---" | cut -d'|' -f$2 | sed 's#/[^ |]*/##g' | tr -s ' '; }
for round in 1 2; do
  for b in old new; do
    R=$OLD; [ $b = new ] && R=$NEW
    $R bench rays --frames 10 --out $OUT/t3_${b}_$round >/dev/null 2>$OUT/t3_${b}_$round.err || tail -2 $OUT/t3_${b}_$round.err
  done
done
for round in 1 2; do for b in old new; do
  echo "== table 3, $b binary, round $round (test, back-end, GPU ms, GR/s, RFPS)"; t3 $OUT/t3_${b}_$round 2,3,5,8,10
done; done
for mode in raster hybrid full-rt; do
  for s in box atrium; do
    for b in old new; do
      R=$OLD; [ $b = new ] && R=$NEW
      $R render --mode $mode --scene $s --backend compute --width 1280 --height 720 --frames 1 --out $OUT/img/${mode}_${s}_$b.png > /dev/null 2>&1
    done
    cmp -s $OUT/img/${mode}_${s}_old.png $OUT/img/${mode}_${s}_new.png && echo "$mode $s: images identical" || echo "$mode $s: images DIFFER"
  done
done
cd $OUT && tar czf results.tgz t3_* img 2>/dev/null; rm -rf t3_* img
