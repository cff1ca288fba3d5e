#!/bin/bash
# The GPU-machine run for "a static scene costs nothing per frame" (issue: fast around the GPU
# too): the frame's wall time and its parts outside the passes on static scenes of growing size,
# before (.gpu/raygraph-old, 3ba65a9: the baseline, every mesh hashed every frame) and
# after (.gpu/raygraph: meshes behind Arcs, their hashes and bounds kept while unchanged).
# 2560x1440, `render --frames 60 --backend compute`, full RT and raster, after a warm-up run.
# Each binary runs from an empty folder (a file of the working tree's shaders/ would override
# the old binary's built-in copy). Prints the passes' totals, the wall time and, for the new
# binary, the parts outside the passes (3ba65a9 ends 16.8M triangles with a stack overflow).
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
for b in raygraph raygraph-old; do [ -f .gpu/$b.gz ] && gunzip -f .gpu/$b.gz && chmod +x .gpu/$b; done
OLD=$PWD/.gpu/raygraph-old; NEW=$PWD/.gpu/raygraph
$NEW bench rays --scenes box --backend compute --frames 5 --out /tmp/warm 2>&1 | grep -iE "adapter" | head -1
for scene in "atrium" "atrium --duplicate 2 --no-dedup" "atrium --duplicate 3 --no-dedup" "atrium --duplicate 4 --no-dedup"; do
  for mode in full-rt raster; do
    for b in old new; do
      R=$OLD; [ $b = new ] && R=$NEW
      mkdir -p /tmp/empty_$b && cd /tmp/empty_$b
      echo "== $scene, $mode, $b binary"
      $R render --scene $scene --mode $mode --backend compute --width 2560 --height 1440 --frames 60 --out /tmp/o.png 2>&1 | grep -E "duplicated|^total|frame wall|outside the passes|overflow|error"
      cd - >/dev/null
    done
  done
done
