#!/bin/bash
# The GPU-machine run for the glTF conformance work (issue: glTF conformance): scenes without the
# new features pay nothing for them. Two binaries in one call, alternating: .gpu/raygraph-old
# (3ba65a9, before the work) and .gpu/raygraph (after it): Table 3 (`bench rays`) twice each, and
# the real-asset rows twice each on copies of the two real assets that carry the old default view
# as their first camera (.gpu/*_oldview.glb, written by the old binary's `scene export`: the new
# default view looks from the front, so the files' own views would differ between binaries).
# Each binary runs from an empty folder: a file of the working tree's shaders/ would override the
# old binary's built-in copy. Results land in $OUT/results.tgz; the short table is printed last.
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
# The binaries travel gzipped (the working tree and the carried folder may take 64 MiB).
for b in raygraph raygraph-old; do [ -f .gpu/$b.gz ] && gunzip -f .gpu/$b.gz && chmod +x .gpu/$b; done
OLD=$PWD/.gpu/raygraph-old; NEW=$PWD/.gpu/raygraph
ASSETS=$PWD/.gpu/helmet_oldview.glb,$PWD/.gpu/pine_oldview.gltf
$NEW bench rays --scenes box --backend compute --frames 5 --out /tmp/warm 2>&1 | grep -iE "adapter" | head -1
t3() { grep -E "^\| " $1/rays.md | grep -v -- "---" | cut -d'|' -f$2 | sed 's#/[^ |]*/##g' | tr -s ' '; }
for round in 1 2; do
  for b in old new; do
    R=$OLD; [ $b = new ] && R=$NEW
    mkdir -p /tmp/empty_$b && cd /tmp/empty_$b
    $R bench rays --frames 10 --out $OUT/t3_${b}_$round >/dev/null 2>$OUT/t3_${b}_$round.err || tail -2 $OUT/t3_${b}_$round.err
    $R bench rays --scenes $ASSETS --frames 10 --out $OUT/ra_${b}_$round >/dev/null 2>$OUT/ra_${b}_$round.err || tail -2 $OUT/ra_${b}_$round.err
    # The raster graph's passes (Table 3's RFPS) one by one, after the warm-up above.
    for s in box organic atrium; do
      $R render --mode raster --scene $s --width 2560 --height 1440 --frames 300 --out /tmp/r.png 2>/dev/null | grep -E "^(forward|shadow_map/shadow_map |tonemap|total)" > $OUT/rp_${b}_${round}_$s.txt
    done
    cd - >/dev/null
  done
done
for round in 1 2; do for b in old new; do
  echo "== table 3, $b binary, round $round (test, back-end, GPU ms, wall ms, GR/s, RFPS)"; t3 $OUT/t3_${b}_$round 2,3,5,6,8,10
  echo "== real assets (old view), $b binary, round $round"; t3 $OUT/ra_${b}_$round 2,3,5,6,8,10
  for s in box organic atrium; do echo "== raster passes, $s, $b binary, round $round (GPU ms, CPU ms)"; cat $OUT/rp_${b}_${round}_$s.txt; done
done; done
cd $OUT && tar czf results.tgz t3_* ra_* rp_* 2>/dev/null; rm -rf t3_* ra_* rp_*
