#!/bin/bash
# The H100 run that closes 2026-11-26: the self-test, 10,000-frame soaks per back-end, Table 3
# and the real assets on both back-ends, hybrid and raster per pass with the visibility-buffer
# layers against the fragment-stage ones, the GPU builder and cache rebuild, and the hybrid
# against full-RT comparison of `bench error`. Everything lands in $OUT/results.tgz.
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
R=$PWD/.gpu/raygraph; H=$PWD/assets/gltf/DamagedHelmet/DamagedHelmet.glb; P=$PWD/assets/gltf/smallpine/scene.gltf
mkdir -p $OUT/h100 $OUT/r
$R render --scene box --backend compute --width 64 --height 64 --frames 1 --out /tmp/x.png 2>&1 | grep -iE "adapter:" | head -1
$R selftest --out $OUT/h100 > $OUT/h100/selftest.stdout 2>&1; echo "selftest exit $?"; grep -E "passed|FAILED|not applicable" $OUT/h100/selftest.stdout | head -20
for b in compute rt-pipeline; do
  $R soak --frames 10000 --cycle 500 --backend $b --log $OUT/h100/soak-$b.log > $OUT/h100/soak-$b.stdout 2>&1; echo "soak $b exit $?"; tail -3 $OUT/h100/soak-$b.stdout
done
$R bench rays --scenes box --backend compute --frames 5 --out /tmp/warm >/dev/null 2>&1
t3() { grep -E "^\| " $1/rays.md | grep -v -- "---" | cut -d'|' -f$2 | sed 's#/[^ |]*/##g' | tr -s ' '; }
$R bench rays --frames 10 --out $OUT/table3 >/dev/null 2>$OUT/table3.err || tail -2 $OUT/table3.err
echo "== table 3 (test, back-end, GPU ms, wall ms, GR/s, hit, RFPS)"; t3 $OUT/table3 2,3,5,6,8,9,10
$R bench rays --scenes $H,$P --frames 10 --out $OUT/real >/dev/null 2>$OUT/real.err || tail -2 $OUT/real.err
echo "== real assets (test, back-end, GPU ms, GR/s, hit, RFPS, camera)"; t3 $OUT/real 2,3,5,8,9,10,13
mkdir -p graph && sed 's/layer: "deferred"/layer: "deferred_fragment"/' graph/hybrid.ron > graph/hybrid_fragment.ron
sed 's/layer: "forward"/layer: "forward_fragment"/' graph/raster.ron > graph/raster_fragment.ron
for g in hybrid hybrid_fragment raster raster_fragment; do
  for s in box atrium $H; do
    n=$(basename $s .glb)
    $R render --graph graph/$g.ron --scene $s --backend compute --width 2560 --height 1440 --frames 10 --out /tmp/o.png > $OUT/r/${g}_${n}.txt 2>&1
    echo "$g $n: $(grep -E '^(gbuffer/|forward/|shadow_map/shadow_map |total)' $OUT/r/${g}_${n}.txt | awk '{print $1, $3}' | tr '\n' ' ')"
  done
done
$R bench build --scenes box,organic,atrium --max-factor 1 --out $OUT/build >/dev/null 2>$OUT/build.err || tail -3 $OUT/build.err
echo "== bench build"; grep -E "^\| " $OUT/build/gpu_build.md | tr -s ' '
timeout 150 $R bench error --backend compute --out $OUT/error >/dev/null 2>$OUT/error.err; echo "bench error exit $?"
ls $OUT/error 2>/dev/null | head; grep -A8 -i "hybrid" $OUT/error/*.md 2>/dev/null | head -20
cd $OUT && tar czf results.tgz h100 r table3 real build error *.err 2>/dev/null; rm -rf h100 r table3 real build error *.err
