#!/bin/bash
# The H100 run after the visibility buffer, the uncleared traversal stack, built-in layers
# without loop bounding and the GPU rebuild without read-back: raster per pass with the
# visibility-buffer `forward` layer against `forward_fragment` (same binary, a graph file
# naming it), Table 3 and the real assets on both back-ends, the helmet's scene workload per
# pass on both back-ends, and the GPU builder with the cache rebuild's wall time.
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
R=$PWD/.gpu/raygraph; H=$PWD/assets/gltf/DamagedHelmet/DamagedHelmet.glb; P=$PWD/assets/gltf/smallpine/scene.gltf
$R render --scene box --backend compute --width 64 --height 64 --frames 1 --out /tmp/x.png 2>&1 | grep -iE "adapter:" | head -1
$R bench rays --scenes box --backend compute --frames 5 --out /tmp/warm >/dev/null 2>&1
mkdir -p $OUT/r graph && sed 's/layer: "forward"/layer: "forward_fragment"/' graph/raster.ron > graph/raster_fragment.ron
for i in 1 2; do
  for g in raster raster_fragment; do
    for s in box organic atrium $H $P; do
      n=$(basename $s .glb)
      $R render --graph graph/$g.ron --scene $s --backend compute --width 2560 --height 1440 --frames 10 --out /tmp/o.png > $OUT/r/${g}_${n}_$i.txt 2>&1
      echo "$g $n $i: $(grep -E '^(forward|total)' $OUT/r/${g}_${n}_$i.txt | awk '{print $1, $3}' | tr '\n' ' ')"
    done
  done
done
t3() { grep -E "^\| " $1/rays.md | grep -v -- "---" | cut -d'|' -f$2 | sed 's#/[^ |]*/##g' | tr -s ' '; }
$R bench rays --frames 10 --out $OUT/table3 >/dev/null 2>$OUT/table3.err || tail -2 $OUT/table3.err
echo "== table 3 (test, back-end, GPU ms, wall ms, GR/s, hit, RFPS)"; t3 $OUT/table3 2,3,5,6,8,9,10
$R bench rays --scenes $H,$P --frames 10 --out $OUT/real >/dev/null 2>$OUT/real.err || tail -2 $OUT/real.err
echo "== real assets (test, back-end, GPU ms, GR/s, hit, RFPS, camera)"; t3 $OUT/real 2,3,5,8,9,10,13
for b in compute rt-pipeline; do
  $R render --graph graph/bench_rays.ron --scene $H --backend $b --width 2560 --height 1440 --frames 10 --out /tmp/o.png > $OUT/r/helmet_passes_$b.txt 2>&1
  echo "helmet bench_rays $b: $(grep -E '^(gbuffer|shadow|ao|total)' $OUT/r/helmet_passes_$b.txt | awk '{print $1, $3}' | tr '\n' ' ')"
done
$R bench build --scenes box,organic,atrium --max-factor 1 --out $OUT/build >/dev/null 2>$OUT/build.err || tail -3 $OUT/build.err
echo "== bench build"; grep -E "^\| " $OUT/build/gpu_build.md | tr -s ' '
cd $OUT && tar czf results.tgz r table3 real build *.err && rm -rf r table3 real build *.err
