#!/bin/bash
# naga's loop bounding in the built-in layer shaders on the H100: one binary, with it
# (RAYGRAPH_SHADER_CHECKS=all, which also bounds the trace passes' loops) and without it (the
# default for built-in files), alternating; raster and hybrid per-pass GPU ms at 2560x1440,
# then Table 3 with its RFPS column both ways.
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
R=$PWD/.gpu/raygraph; H=$PWD/assets/gltf/DamagedHelmet/DamagedHelmet.glb; P=$PWD/assets/gltf/smallpine/scene.gltf
$R render --scene box --backend compute --width 64 --height 64 --frames 1 --out /tmp/x.png 2>&1 | grep -iE "adapter:" | head -1
$R bench rays --scenes box --backend compute --frames 5 --out /tmp/warm >/dev/null 2>&1
mkdir -p $OUT/r
for i in 1 2; do
  for c in all default; do
    for m in raster hybrid; do
      for s in box organic atrium $H $P; do
        n=$(basename $s .glb)
        RAYGRAPH_SHADER_CHECKS=$c $R render --mode $m --scene $s --backend compute --width 2560 --height 1440 --frames 10 --out /tmp/o.png > $OUT/r/${c}_${m}_${n}_$i.txt 2>&1
        echo "$c $m $n $i: $(grep -E '^total' $OUT/r/${c}_${m}_${n}_$i.txt | tr -s ' ')"
      done
    done
  done
done
for c in all default; do
  RAYGRAPH_SHADER_CHECKS=$c $R bench rays --backend compute --frames 10 --out $OUT/t3_$c >/dev/null 2>$OUT/t3_$c.err || tail -2 $OUT/t3_$c.err
  echo "== table 3, compute, RAYGRAPH_SHADER_CHECKS=$c (test, GPU ms, GR/s, RFPS)"; grep -E "^\| " $OUT/t3_$c/rays.md | grep -v -- "---" | cut -d'|' -f2,5,8,10 | tr -s ' '
done
cd $OUT && tar czf results.tgz r t3_* && rm -rf r t3_*
