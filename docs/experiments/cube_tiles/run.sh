#!/bin/bash
# A cube map's six faces in one render pass (`shadow_tiles`) against six passes, on the GPU
# machine, then the CPU time outside the passes of the built-in graphs at 262k and 7.1M
# triangles with the new build.
# 1. docs/experiments/point_shadows/ab.sh with .gpu/raygraph_old.gz (abf9c61: one pass a face)
#    and .gpu/raygraph_new.gz: raster of atrium-lights, of its 2x2x2 copy (unique triangles)
#    and of the atrium, old and new alternating, twice; images compared with cmp.
# 2. The new build alone, `render --frames 120` at 2560x1440 on `compute`, with each way of
#    waiting for the GPU (RAYGRAPH_GPU_WAIT=block, tail, spin: src/runtime/gpu_wait.rs) in turn,
#    twice: raster of atrium-lights, and raster, hybrid, full RT and hybrid_denoised of the
#    atrium; then once, block and tail, raster, hybrid and full RT of the atrium duplicated
#    3x3x3 with unique triangles (7.1M).
# Logs in $OUT/cube_tiles_ab.tgz and $OUT/cube_tiles_sweep.tgz; the rows printed.
# `run.sh ab` runs part 1, `run.sh sweep` part 2 (each within one device call).
set -u
ROOT=$PWD; OUT=${OUT:-/tmp/out}
if [ "${1:-ab}" = ab ]; then
  RUNS="raster:atrium-lights raster:atrium-lights-dup2 raster:atrium" bash docs/experiments/point_shadows/ab.sh
  mv $OUT/point_shadows_ab.tgz $OUT/cube_tiles_ab.tgz
  exit
fi
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
gunzip -f .gpu/raygraph_new.gz; chmod +x .gpu/raygraph_new
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
mkdir -p /tmp/sweep $OUT/s && cd /tmp/sweep
sweep() { # rounds, rows (MODE[:dup3]), wait modes
  for round in $(seq 1 $1); do
    for run in $2; do
      for wait in $3; do
        mode=${run%%:*}; scene=atrium; extra=""
        [ "$run" != "$mode" ] && extra="--duplicate 3 --no-dedup"
        graph="--mode $mode"; [ $mode = denoised ] && graph="--graph $ROOT/graph/hybrid_denoised.ron"
        [ $mode = lights ] && graph="--mode raster" && scene=atrium-lights
        log=$OUT/s/${mode}${extra:+_dup3}_${wait}_$round.log
        RAYGRAPH_GPU_WAIT=$wait timeout 240 $ROOT/.gpu/raygraph_new render $graph --scene $scene $extra --backend compute --width 2560 --height 1440 --frames 120 --out /tmp/sweep/x.png > $log 2>&1 || tail -3 $log
        echo "== $mode ${extra:+7.1M} wait $wait round $round"; grep -E "^(total|frame wall|outside)" $log
      done
    done
  done
}
sweep 2 "lights raster hybrid full-rt denoised" "block tail spin"
sweep 1 "raster:dup3 hybrid:dup3 full-rt:dup3" "block tail"
cd $OUT && tar czf cube_tiles_sweep.tgz s && rm -rf s
