#!/bin/bash
# The traversal stack's clear on the H100: one binary, trace modules from WGSL (the stack
# cleared per invocation, RAYGRAPH_CLEARED_STACK=1) against SPIR-V without the clear (the
# default), alternating, compute back-end; then Table 3 and the shared real assets on both
# back-ends with the default, and the real assets on compute with the clear.
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
R=$PWD/.gpu/raygraph; H=$PWD/assets/gltf/DamagedHelmet/DamagedHelmet.glb; P=$PWD/assets/gltf/smallpine/scene.gltf
RUST_LOG=info $R render --scene box --backend compute --width 64 --height 64 --frames 1 --out /tmp/x.png 2>&1 | grep -iE "adapter:|traversal stack" | head -2
$R bench rays --scenes box --backend compute --frames 5 --out /tmp/warm >/dev/null 2>&1
t3() { grep -E "^\| " $1/rays.md | grep -v -- "---" | cut -d'|' -f$2 | sed 's#/[^ |]*/##g' | tr -s ' '; }
for i in 1 2; do
  for c in 1 0; do
    d=$OUT/cleared${c}_$i
    RAYGRAPH_CLEARED_STACK=$c $R bench rays --backend compute --frames 10 --out $d >/dev/null 2>$d.err || tail -2 $d.err
    echo "== table 3, compute, RAYGRAPH_CLEARED_STACK=$c, run $i (test, GPU ms, wall ms, GR/s, RFPS)"; t3 $d 2,5,6,8,10
  done
done
$R bench rays --frames 10 --out $OUT/table3 >/dev/null 2>$OUT/table3.err || tail -2 $OUT/table3.err
echo "== table 3, both back-ends (test, back-end, GPU ms, wall ms, GR/s, hit, RFPS, scene)"; t3 $OUT/table3 2,3,5,6,8,9,10,12
for s in $H $P; do
  n=$(basename $s .glb); d=$OUT/real_$n
  $R bench rays --scenes $s --frames 10 --out $d >/dev/null 2>$d.err || tail -2 $d.err
  echo "== $n, both back-ends (test, back-end, GPU ms, GR/s, hit, camera)"; t3 $d 2,3,5,8,9,13
  RAYGRAPH_CLEARED_STACK=1 $R bench rays --scenes $s --backend compute --frames 10 --out ${d}_cleared >/dev/null 2>${d}_cleared.err || tail -2 ${d}_cleared.err
  echo "== $n, compute, cleared (test, GPU ms, GR/s)"; t3 ${d}_cleared 2,5,8
done
