#!/bin/bash
# Raster point-light shadows against the build before them, on the GPU machine: two release
# binaries (.gpu/raygraph_old.gz, built from c80102b, and .gpu/raygraph_new.gz), each run in an
# empty folder so that it reads its own built-in graph, layers and shaders. `render --frames 60`
# at 2560x1440 on `compute`: raster of atrium-lights (1,024 point lights; the new build draws
# cube maps for two) and of the atrium (a sun), hybrid of the atrium; old and new alternating,
# twice. RUNS overrides the rows (MODE:SCENE, a scene ending in -dup2 duplicated 2x2x2 with
# unique triangles). The
# passes' total, the cube-map faces, the wall time and the CPU time outside the passes in
# $OUT/point_shadows_ab.tgz; the rows printed last.
set -u
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
for b in old new; do gunzip -f .gpu/raygraph_$b.gz; chmod +x .gpu/raygraph_$b; done
ROOT=$PWD; OUT=${OUT:-/tmp/out}; mkdir -p $OUT/r /tmp/ab
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
cd /tmp/ab
for round in 1 2; do
  for run in ${RUNS:-raster:atrium-lights raster:atrium hybrid:atrium}; do
    mode=${run%%:*}; scene=${run#*:}
    extra=""; case $scene in *-dup2) scene=${scene%-dup2}; extra="--duplicate 2 --no-dedup";; esac
    for b in old new; do
      log=$OUT/r/${b}_${mode}_${scene}${extra:+_dup2}_$round.log
      timeout 150 $ROOT/.gpu/raygraph_$b render --mode $mode --scene $scene $extra --backend compute --width 2560 --height 1440 --frames 60 --out /tmp/ab/x.png > $log 2>&1 || tail -3 $log
      faces=$(grep -E "^shadow_map/cube" $log | awk '{s += $3} END {printf "%.3f", s}')
      echo "== $b $mode $scene $extra round $round: cube faces ${faces} ms"; grep -E "^(total|frame wall|outside)" $log
      cmp -s /tmp/ab/x.png /tmp/ab/prev.png && echo "(image identical to the previous binary's)"; mv /tmp/ab/x.png /tmp/ab/prev.png
    done
  done
done
cd $OUT && tar czf point_shadows_ab.tgz r 2>/dev/null; rm -rf r
