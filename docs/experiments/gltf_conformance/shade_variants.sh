#!/bin/bash
# The GPU-machine run of the shade-pass variants (shade_variants.py builds them): the raster
# graph's passes on box, organic and atrium at 2560x1440, 300 frames after a warm-up, for the
# binary before the conformance work (.gpu/raygraph-old), after it (.gpu/raygraph) and each
# variant, two rounds, alternating; each from an empty folder (the built-in shaders).
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
for g in .gpu/*.gz; do gunzip -f $g; done; chmod +x .gpu/raygraph*
BINS="old new no_ortho no_extras"
ROOT=$PWD
bin() { [ $1 = new ] && echo $ROOT/.gpu/raygraph || echo $ROOT/.gpu/raygraph-$1; }
$(bin new) bench rays --scenes box --backend compute --frames 5 --out /tmp/warm 2>&1 | grep -iE "adapter" | head -1
for round in 1 2; do for b in $BINS; do
  mkdir -p /tmp/empty_$b && cd /tmp/empty_$b
  for s in box organic atrium; do
    $(bin $b) render --mode raster --scene $s --width 2560 --height 1440 --frames 300 --out /tmp/r.png 2>$OUT/sv_${b}_${round}_$s.err | grep -E "^(forward/shade|total)" > $OUT/sv_${b}_${round}_$s.txt
  done
  cd - >/dev/null
done; done
for s in box organic atrium; do for b in $BINS; do
  echo "$s $b: shade ms $(for r in 1 2; do awk '/forward\/shade/ {printf "%s ", $3}' $OUT/sv_${b}_${r}_$s.txt; done) total ms $(for r in 1 2; do awk '/total/ {printf "%s ", $3}' $OUT/sv_${b}_${r}_$s.txt; done)"
done; done
cd $OUT && tar czf shade_variants.tgz sv_* && rm -f sv_*
