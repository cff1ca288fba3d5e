#!/bin/bash
# Table 3 before (80fd135) and after this session's restructuring, alternating, then the
# warm-up check (eight helmet rows in one process) and the real assets, on one machine.
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
R=$PWD/.gpu/raygraph; B=$PWD/.gpu/raygraph_base
H=$PWD/assets/gltf/DamagedHelmet/DamagedHelmet.glb; P=$PWD/assets/gltf/smallpine/scene.gltf
$R render --scene box --width 64 --height 64 --frames 1 --out /tmp/x.png 2>&1 | grep -i "adapter:" | head -1
$R bench rays --scenes box --backend compute --frames 5 --out /tmp/warm >/dev/null 2>&1
t3() { grep -E "^\| (box|organic|atrium|Miss|Stress) " $1/rays.md | cut -d'|' -f$2 | tr -s ' '; }
for i in 1 2; do
  (cd .gpu/base && $B bench rays --frames 10 --out $OUT/base$i >/dev/null 2>$OUT/base$i.err) || tail -2 $OUT/base$i.err
  echo "== base $i (test, back-end, GPU ms, GR/s, RFPS)"; t3 $OUT/base$i 2,3,5,7,9
  $R bench rays --frames 10 --out $OUT/new$i >/dev/null 2>$OUT/new$i.err || tail -2 $OUT/new$i.err
  echo "== new $i (test, back-end, GPU ms, wall ms, GR/s, RFPS)"; t3 $OUT/new$i 2,3,5,6,8,10
done
$R bench rays --scenes $H,$H,$H,$H,$H,$H,$H,$H --backend compute --frames 10 --out $OUT/helmet8 >/dev/null 2>$OUT/helmet8.err
echo "== helmet x8 (GPU ms)"; grep DamagedHelmet $OUT/helmet8/rays.md | cut -d'|' -f5 | tr '\n' ' '; echo
$R bench rays --scenes $H,$P --frames 10 --out $OUT/real >/dev/null 2>$OUT/real.err || tail -2 $OUT/real.err
echo "== real assets"; grep -E "^\| " $OUT/real/rays.md | grep -v -- "---" | cut -d'|' -f2-10 | sed 's#/[^ |]*/##' | tr -s ' '
for s in $H $P; do echo "-- render bench_rays $(basename $s) compute"; $R render --graph graph/bench_rays.ron --scene $s --backend compute --width 2560 --height 1440 --frames 10 --out /tmp/o.png 2>/dev/null | grep -E "total|wall"; done
