#!/bin/bash
# The H100 run for closed-mesh culling in shadow maps and real out-of-memory: Table 3 and the
# real assets re-run; the shadow-map passes with the shipped layer against a copy that draws
# both sides of everything (alternating, same binary); the hybrid graph at 32768x32768 (about
# 88 GiB of render targets) over an earlier output file; the atrium duplicated 11x11x11 with a
# mesh per copy. Everything lands in $OUT/results.tgz.
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
R=$PWD/.gpu/raygraph; H=$PWD/assets/gltf/DamagedHelmet/DamagedHelmet.glb; P=$PWD/assets/gltf/smallpine/scene.gltf
mkdir -p $OUT/r $OUT/oom
$R bench rays --scenes box --backend compute --frames 5 --out /tmp/warm 2>&1 | grep -iE "adapter" | head -1
t3() { grep -E "^\| " $1/rays.md | grep -v -- "---" | cut -d'|' -f$2 | sed 's#/[^ |]*/##g' | tr -s ' '; }
$R bench rays --frames 10 --out $OUT/table3 >/dev/null 2>$OUT/table3.err || tail -2 $OUT/table3.err
echo "== table 3 (test, back-end, GPU ms, wall ms, GR/s, hit, RFPS)"; t3 $OUT/table3 2,3,5,6,8,9,10
$R bench rays --scenes $H,$P --frames 10 --out $OUT/real >/dev/null 2>$OUT/real.err || tail -2 $OUT/real.err
echo "== real assets (test, back-end, GPU ms, GR/s, hit, RFPS, camera)"; t3 $OUT/real 2,3,5,8,9,10,13
# The shadow-map layer drawing both sides of everything, as before closed-mesh culling.
mkdir -p /tmp/both/layers && cp -r layers/* /tmp/both/layers/ && sed -i 's/cull_closed_back_faces: true/cull_closed_back_faces: false/' /tmp/both/layers/shadow_map.ron
for round in 1 2; do
  for variant in culled both; do
    L=""; [ $variant = both ] && L="--layers /tmp/both/layers"
    for s in box organic atrium; do
      $R render --mode raster $L --scene $s --backend compute --width 2560 --height 1440 --frames 20 --out $OUT/r/${s}_${variant}.png > $OUT/r/${s}_${variant}_$round.txt 2>&1
      echo "round $round $variant $s: $(grep -E '^(shadow_map/shadow_map |total)' $OUT/r/${s}_${variant}_$round.txt | awk '{print $1, $3}' | tr '\n' ' ')"
    done
  done
done
for s in box organic atrium; do cmp -s $OUT/r/${s}_culled.png $OUT/r/${s}_both.png && echo "$s: images identical" || echo "$s: images DIFFER"; done
# Real out-of-memory: an earlier output, then a frame whose render targets exceed the GPU.
$R render --mode hybrid --scene atrium --backend compute --width 256 --height 256 --frames 1 --out $OUT/oom/out.png > /dev/null 2>&1
sha256sum $OUT/oom/out.png > $OUT/oom/before.sha
nvidia-smi --query-gpu=memory.total,memory.used --format=csv > $OUT/oom/nvidia-smi.txt 2>&1
timeout 240 /usr/bin/time -v $R render --mode hybrid --scene atrium --backend compute --width 32768 --height 32768 --frames 1 --out $OUT/oom/out.png > $OUT/oom/big.stdout 2> $OUT/oom/big.stderr
echo "32768x32768 exit $?"; grep -vE "^\s" $OUT/oom/big.stderr | tail -4; grep -E "Maximum resident|Elapsed" $OUT/oom/big.stderr
sha256sum -c $OUT/oom/before.sha
timeout 300 /usr/bin/time -v $R render --mode hybrid --scene atrium --backend compute --duplicate 11 --no-dedup --width 256 --height 256 --frames 1 --out $OUT/oom/out.png > $OUT/oom/dup.stdout 2> $OUT/oom/dup.stderr
echo "duplicate 11 exit $?"; cat $OUT/oom/dup.stdout | tail -2; grep -vE "^\s" $OUT/oom/dup.stderr | tail -3; grep -E "Maximum resident|Elapsed" $OUT/oom/dup.stderr
sha256sum -c $OUT/oom/before.sha
cd $OUT && tar czf results.tgz r oom table3 real *.err 2>/dev/null; rm -rf r oom table3 real *.err
