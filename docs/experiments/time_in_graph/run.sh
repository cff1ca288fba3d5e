#!/bin/bash
# The H100 run for history resources, motion vectors, the temporal and à-trous filters, soft
# shadows and GI: Table 3 on compute and rt-pipeline (the G-buffer's position now carries the
# instance), then per pass at 2560x1440 the hybrid graph against the same effects unfiltered
# (graph/hybrid_soft_gi.ron) and filtered (graph/hybrid_denoised.ron) on the atrium and the
# helmet. Everything lands in $OUT/results.tgz.
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
R=$PWD/.gpu/raygraph; H=$PWD/assets/gltf/DamagedHelmet/DamagedHelmet.glb
mkdir -p $OUT/r
$R bench rays --scenes box --backend compute --frames 5 --out /tmp/warm 2>&1 | grep -iE "adapter" | head -1
t3() { grep -E "^\| " $1/rays.md | grep -v -- "---" | cut -d'|' -f$2 | sed 's#/[^ |]*/##g' | tr -s ' '; }
$R bench rays --frames 10 --out $OUT/table3 >/dev/null 2>$OUT/table3.err || tail -2 $OUT/table3.err
echo "== table 3 (test, back-end, GPU ms, wall ms, GR/s, hit, RFPS)"; t3 $OUT/table3 2,3,5,6,8,9,10
for g in hybrid hybrid_soft_gi hybrid_denoised; do
  for s in atrium $H; do
    n=$(basename $s .glb)
    $R render --graph graph/$g.ron --scene $s --backend compute --width 2560 --height 1440 --frames 20 --out $OUT/r/${g}_${n}.png > $OUT/r/${g}_${n}.txt 2>&1
    echo "== $g $n"; grep -E "^(motion|ao|ao_|shadow|shadow_|gi|gi_|reflection|resolve|gbuffer)/|^total" $OUT/r/${g}_${n}.txt | awk '{print $1, $3}' | tr '\n' ' '; echo
  done
done
rm -f $OUT/r/*.png; cd $OUT && tar czf results.tgz r table3 *.err 2>/dev/null; rm -rf r table3 *.err
