#!/bin/bash
# The H100 run for speed against error of the filtered effects: `bench error --filters-only`
# on the compute back-end (AO, soft shadows and GI of graph/hybrid_denoised.ron on the atrium
# and the helmet at 1280x720, 1/2/4/8 rays, noisy and filtered, against references of 2048
# accumulated frames; equal-time table; camera track), then the filters' per-pass cost at
# 2560x1440 on the atrium. Everything lands in $OUT/results.tgz.
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
R=$PWD/.gpu/raygraph
mkdir -p $OUT/r
timeout 480 $R bench error --filters-only --backend compute --out $OUT/filters > $OUT/filters.log 2>&1; echo "bench exit $?"
grep -iE "adapter" $OUT/filters.log | head -1
cat $OUT/filters/filters.md 2>/dev/null | grep -E "^\|" | grep -v -- "---"
$R render --graph graph/hybrid_denoised.ron --scene atrium --backend compute --width 2560 --height 1440 --frames 20 --out $OUT/r/denoised.png > $OUT/r/denoised.txt 2>&1
echo "== hybrid_denoised atrium 2560x1440"; grep -E "^[a-z_]+/[a-z0-9_]+ |^total" $OUT/r/denoised.txt | awk '{print $1, $3}' | tr '\n' ' '; echo
rm -f $OUT/r/*.png; cd $OUT && tar czf results.tgz r filters filters.log 2>/dev/null; rm -rf r filters filters.log
