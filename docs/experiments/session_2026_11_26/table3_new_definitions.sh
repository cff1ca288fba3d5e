#!/bin/bash
# Table 3 with the definitions of 2026-11-26 (Miss outside/inside, Stress with no sky), and the
# shared real assets with their derived Stress views, both back-ends.
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
R=$PWD/.gpu/raygraph; H=$PWD/assets/gltf/DamagedHelmet/DamagedHelmet.glb; P=$PWD/assets/gltf/smallpine/scene.gltf
$R bench rays --scenes box --backend compute --frames 5 --out /tmp/warm >/dev/null 2>&1
show() { grep -E "^\| " $1/rays.md | grep -v -- "---" | cut -d'|' -f2-5,7-10,12-14 | sed 's#/[^ |]*/##g' | tr -s ' '; }
$R bench rays --frames 10 --out $OUT/table3 >/dev/null 2>$OUT/table3.err || tail -3 $OUT/table3.err
echo "== table 3"; show $OUT/table3
for s in $H $P; do
  n=$(basename $s .glb); d=$OUT/real_$n
  $R bench rays --scenes $s --frames 10 --out $d >/dev/null 2>$d.err || tail -3 $d.err
  echo "== $n"; show $d
done
