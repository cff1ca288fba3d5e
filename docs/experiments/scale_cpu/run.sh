#!/bin/bash
# The frame's CPU time outside its passes at 2.1M, 7.1M and 32.8M unique triangles with the
# default wait (a GPU adapter polls: src/runtime/gpu_wait.rs), on the GPU machine: the atrium
# copied 2x2x2, 3x3x3 and 5x5x5 with its own meshes each (`--duplicate N --no-dedup`), raster,
# hybrid and full RT, `render --backend compute --width 2560 --height 1440 --frames 60`, one
# release binary (.gpu/raygraph.xz). Logs in $OUT/scale_cpu.tgz; the rows printed.
set -u
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
xz -dc .gpu/raygraph.xz > .gpu/raygraph; chmod +x .gpu/raygraph
ROOT=$PWD; OUT=${OUT:-/tmp/out}; mkdir -p $OUT/s /tmp/sc
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
cd /tmp/sc
for dup in 2 3 5; do
  for mode in raster hybrid full-rt; do
    if [ $SECONDS -gt 540 ]; then echo "skipped: $mode x$dup"; continue; fi
    log=$OUT/s/${mode}_x$dup.log
    timeout 200 $ROOT/.gpu/raygraph render --mode $mode --scene atrium --duplicate $dup --no-dedup --backend compute --width 2560 --height 1440 --frames 60 --out /tmp/sc/x.png > $log 2>&1 || tail -3 $log
    echo "== $mode atrium x$dup"; grep -E "^(scene duplicated|total|frame wall|outside)" $log
  done
done
cd $OUT && tar czf scale_cpu.tgz s && rm -rf s
