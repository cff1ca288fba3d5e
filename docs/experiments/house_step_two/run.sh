#!/bin/bash
# The GPU machine's run for the restructuring of issue 36 (a thin command line, short functions, the
# scene's upload in runtime/, shared WGSL, narrower visibility): Table 3 and the images unchanged.
# Two release binaries in one call, alternating: .gpu/raygraph-base (8e87ddf, before) and
# .gpu/raygraph (after). Each runs from an empty folder of its own, so that it reads the graph,
# layer and shader files built into it (never the other's). Table 3 (`bench rays --frames 10`)
# twice each; the three modes on the built-in scenes rendered by both on `compute` and compared
# byte for byte. Results land in $OUT/results.tgz; the short table is printed last.
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
gunzip -f .gpu/raygraph-base.gz .gpu/raygraph.gz; chmod +x .gpu/raygraph-base .gpu/raygraph
OLD=$PWD/.gpu/raygraph-base; NEW=$PWD/.gpu/raygraph
mkdir -p $OUT/img /tmp/run_old /tmp/run_new
(cd /tmp/run_new && $NEW bench rays --scenes box --backend compute --frames 5 --out /tmp/warm 2>&1 | grep -iE "adapter" | head -1)
t3() { grep -E "^\| " $1/rays.md | grep -v -- "---" | cut -d'|' -f$2 | sed 's#/[^ |]*/##g' | tr -s ' '; }
for round in 1 2; do
  for b in old new; do
    R=$OLD; [ $b = new ] && R=$NEW
    (cd /tmp/run_$b && $R bench rays --frames 10 --out $OUT/t3_${b}_$round >/dev/null 2>$OUT/t3_${b}_$round.err) || tail -2 $OUT/t3_${b}_$round.err
  done
done
for mode in raster hybrid full-rt; do
  for s in default box organic atrium; do
    for b in old new; do
      R=$OLD; [ $b = new ] && R=$NEW
      (cd /tmp/run_$b && $R render --mode $mode --scene $s --backend compute --width 1280 --height 720 --frames 1 --out $OUT/img/${mode}_${s}_$b.png > /dev/null 2>&1)
    done
    cmp -s $OUT/img/${mode}_${s}_old.png $OUT/img/${mode}_${s}_new.png && echo "$mode $s: images identical" || echo "$mode $s: images DIFFER"
  done
done
for round in 1 2; do for b in old new; do
  echo "== table 3, $b binary, round $round (test, back-end, GPU ms, GR/s, RFPS)"; t3 $OUT/t3_${b}_$round 2,3,5,8,10
done; done
cd $OUT && tar czf results.tgz t3_* img 2>/dev/null; rm -rf t3_* img
