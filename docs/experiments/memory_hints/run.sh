#!/bin/bash
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
R=.gpu/raygraph; H=assets/gltf/DamagedHelmet/DamagedHelmet.glb
$R render --scene box --width 64 --height 64 --out /tmp/x.png 2>&1 | grep -i adapter | head -2
nvidia-smi --query-gpu=name,clocks.sm,memory.used --format=csv,noheader
$R bench rays --scenes box --backend compute --frames 5 --out /tmp/warm >/dev/null 2>&1
i=0
for hint in performance 4-4 memory performance 4-4 256-256; do
  i=$((i+1)); d=$OUT/p${i}_$hint
  RAYGRAPH_MEMORY_HINTS=$hint $R bench rays --scenes box,organic --backend compute --frames 10 --out $d >/dev/null 2>$d.err || tail -3 $d.err
  echo "== $i $hint"; grep -vE "^\| ---" $d/rays.md | grep -E "^\|" | cut -c1-170
done
for hint in performance 4-4 performance 4-4; do
  i=$((i+1)); d=$OUT/h${i}_$hint
  RAYGRAPH_MEMORY_HINTS=$hint $R bench rays --scenes box,$H --frames 10 --out $d >/dev/null 2>$d.err || tail -3 $d.err
  echo "== hazard $i $hint"; grep -vE "^\| ---" $d/rays.md | grep -E "^\|" | cut -c1-170
done
