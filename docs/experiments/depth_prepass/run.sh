#!/bin/bash
# The depth pre-pass on the H100: one release binary built with depth_prepass.patch in .gpu/,
# and two copies of graph/, layers/ and shaders/ beside it, .gpu/on (as the patch leaves them)
# and .gpu/off (`depth_prepass: false` in layers/forward.ron and layers/deferred.ron); the
# binary reads the files on disk first. DEVICE notes: ../../../README.md and BENCHMARKS.md.
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
R=$PWD/.gpu/raygraph; H=$PWD/assets/gltf/DamagedHelmet/DamagedHelmet.glb
cd .gpu/on && $R bench rays --scenes box --backend compute --frames 5 --out /tmp/warm >/dev/null 2>&1; cd ../..
i=0
for v in on off on off; do
  i=$((i+1)); cd .gpu/$v
  $R bench rays --scenes box,organic,atrium,$H --backend compute --frames 10 --out $OUT/b${i}_$v >/dev/null 2>$OUT/b$i.err || tail -3 $OUT/b$i.err
  echo "== $i prepass $v"; grep -E "^\| (box|organic|atrium|/)" $OUT/b${i}_$v/rays.md | cut -c1-120
  for m in raster hybrid; do
    for s in atrium $H; do
      echo "-- $m $(basename $s)"; $R render --mode $m --scene $s --backend compute --width 2560 --height 1440 --frames 10 --out /tmp/o.png 2>/dev/null | grep -E "draw|total|wall" | cut -c1-75 | head -5
    done
  done
  cd ../..
done
