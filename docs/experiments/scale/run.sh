#!/bin/bash
# The GPU-machine runs for the wall-time-and-scale issue, in two parts (each within one device
# call). Binaries: .gpu/raygraph-prev (965f747: meshes behind Arcs, instances and materials
# still hashed every frame, one draw call per instance) and .gpu/raygraph (the scene followed
# by pointer, raster draws as indirect commands, `bench scale`). Every binary runs from an
# empty folder but for the repository's graph/layers/shaders where a bench needs them.
#   part 1: a static scene's frame, before and after: `render --frames 60` at 2560x1440,
#           compute back-end, full RT and raster, the atrium copied 1 to 4 times per axis
#           without de-duplication (and 5, after only); then `bench build` and `bench rays`
#           each run twice (the 3% agreement rule of BENCHMARKS.md).
#   part 2: `bench scale` (compute and rt-pipeline).
#   part 3: after the fixes part 1 called for (no indirect-draw validation; buffers grown no
#           further than one binding): the raster rows of 7.1M-32.8M triangles and the
#           32.8M full-RT row again (new binary), and `bench build` twice.
#   part 4: `bench rays` on the built-in scenes and the real assets with the previous binary
#           and the new one (SKIP_COVERAGE=1: only that; it measured the AO rays shared out over
#           the workgroup, docs/experiments/pixel_rays/), then (ONLY_COVERAGE=1: only this) the
#           real assets at 2%, 5% and 10% of the frame and a 1.93M-triangle file (the helmet
#           copied 5x5x5 without de-duplication, `scene export`), new binary.
#   part 5: `bench rays` on the built-in scenes, then on the real assets with the coverage rows
#           and the 1.93M-triangle file, previous binary and new one in turn (AO rays over
#           four lanes a pixel; shadow and AO rays through translucent surfaces in one traversal).
#   part 6: `bench rays` on the pine and the 1.93M-triangle file with the coverage rows,
#           previous binary and new one in turn (one read of the alpha texture a candidate of
#           a transmittance ray).
# Results go to $OUT.
set -u
PART=${1:-1}
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
for b in raygraph raygraph-prev; do [ -f .gpu/$b.gz ] && gunzip -f .gpu/$b.gz && chmod +x .gpu/$b; done
PREV=$PWD/.gpu/raygraph-prev; NEW=$PWD/.gpu/raygraph; ROOT=$PWD
OUT=${OUT:-/tmp/out}; mkdir -p $OUT
nvidia-smi --query-gpu=name,driver_version,clocks.sm --format=csv,noheader
$NEW bench rays --scenes box --backend compute --frames 5 --out /tmp/warm 2>&1 | grep -iE "adapter" | head -1
if [ "$PART" = 1 ]; then
  for scene in "atrium" "atrium --duplicate 2 --no-dedup" "atrium --duplicate 3 --no-dedup" "atrium --duplicate 4 --no-dedup" "atrium --duplicate 5 --no-dedup"; do
    for mode in full-rt raster; do
      for b in prev new; do
        R=$PREV; [ $b = new ] && R=$NEW
        case "$scene" in *"duplicate 5"*) [ $b = prev ] && continue;; esac
        mkdir -p /tmp/empty_$b && cd /tmp/empty_$b
        echo "== $scene, $mode, $b binary"
        $R render --scene $scene --mode $mode --backend compute --width 2560 --height 1440 --frames 60 --out /tmp/o.png 2>&1 | grep -E "^total|frame wall|outside the passes|overflow|error"
        cd - >/dev/null
      done
    done
  done 2>&1 | tee $OUT/static_scene.txt
  for k in 1 2; do
    $NEW bench build --scenes organic,atrium --max-factor 1 --backend compute --out $OUT/build_$k > $OUT/build_$k.log 2>&1
    $NEW bench rays --scenes atrium,.gpu/helmet_oldview.glb --out $OUT/rays_$k > $OUT/rays_$k.log 2>&1
  done
  for k in 1 2; do echo "== build run $k"; cat $OUT/build_$k/gpu_build.md | grep -E "^\| (organic|atrium)"; echo "== rays run $k"; grep -E "^\| " $OUT/rays_$k/rays.md | cut -c1-160; done
  cd $OUT && tar czf results.tgz build_1 build_2 rays_1 rays_2 && rm -rf build_1 build_2 rays_1 rays_2 /tmp/warm
elif [ "$PART" = 4 ]; then
  REAL=$ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb,$ROOT/assets/gltf/smallpine/scene.gltf
  # The previous binary runs where there is no shaders/ folder (the working tree's WGSL would
  # replace its built-in copy): the graph and layer files only.
  mkdir -p /tmp/prevroot && cp -r graph layers /tmp/prevroot/
  [ "${ONLY_COVERAGE:-0}" = 1 ] || for b in prev new; do
    R=$PREV; D=/tmp/prevroot; [ $b = new ] && R=$NEW && D=$ROOT
    (cd $D && $R bench rays --frames 10 --out $OUT/rays_builtin_$b > $OUT/rays_builtin_$b.log 2>&1)
    (cd $D && $R bench rays --scenes $REAL --frames 10 --out $OUT/rays_real_$b > $OUT/rays_real_$b.log 2>&1)
  done
  [ "${SKIP_COVERAGE:-0}" = 1 ] && { for f in rays_builtin_prev rays_builtin_new rays_real_prev rays_real_new; do echo "== $f"; grep -E "^\\| " $OUT/$f/rays.md | cut -d'|' -f2-9; done; exit 0; }
  $NEW scene export $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb /tmp/helmet_5x5x5.glb --duplicate 5 --no-dedup
  $NEW bench rays --scenes $REAL,/tmp/helmet_5x5x5.glb --coverage 0.02,0.05,0.1 --frames 10 --out $OUT/rays_coverage > $OUT/rays_coverage.log 2>&1
  for f in rays_builtin_prev rays_builtin_new rays_real_prev rays_real_new rays_coverage; do
    [ -f $OUT/$f/rays.md ] && echo "== $f" && grep -E "^\| " $OUT/$f/rays.md | cut -d'|' -f2-9
  done
  cd $OUT && tar czf results.tgz rays_* && rm -rf rays_builtin_prev rays_builtin_new rays_real_prev rays_real_new rays_coverage
elif [ "$PART" = 5 ]; then
  REAL=$ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb,$ROOT/assets/gltf/smallpine/scene.gltf,/tmp/helmet_5x5x5.glb
  # The previous binary's own graph and layer files (.gpu/prevroot.tgz: `git archive` of its
  # commit), since the layers changed.
  mkdir -p /tmp/prevroot && tar xzf .gpu/prevroot.tgz -C /tmp/prevroot
  $NEW scene export $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb /tmp/helmet_5x5x5.glb --duplicate 5 --no-dedup > /dev/null
  for b in prev new; do
    [ $b = prev ] && [ "${SKIP_PREV:-0}" = 1 ] && continue
    R=$PREV; D=/tmp/prevroot; [ $b = new ] && R=$NEW && D=$ROOT
    (cd $D && $R bench rays --frames 10 --out $OUT/rays_builtin_$b > $OUT/rays_builtin_$b.log 2>&1)
    (cd $D && $R bench rays --scenes $REAL --coverage 0.02,0.05,0.1 --frames 10 --out $OUT/rays_real_$b > $OUT/rays_real_$b.log 2>&1)
  done
  for f in rays_builtin_prev rays_builtin_new rays_real_prev rays_real_new; do
    [ -f $OUT/$f/rays.md ] || continue
    echo "== $f"; grep -E "^\| " $OUT/$f/rays.md | cut -d'|' -f2-9
  done
  cd $OUT && tar czf results.tgz rays_* && rm -rf rays_builtin_prev rays_builtin_new rays_real_prev rays_real_new
elif [ "$PART" = 6 ]; then
  mkdir -p /tmp/prevroot && tar xzf .gpu/prevroot.tgz -C /tmp/prevroot
  $NEW scene export $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb /tmp/helmet_5x5x5.glb --duplicate 5 --no-dedup > /dev/null
  for b in prev new; do
    R=$PREV; D=/tmp/prevroot; [ $b = new ] && R=$NEW && D=$ROOT
    (cd $D && $R bench rays --scenes $ROOT/assets/gltf/smallpine/scene.gltf,/tmp/helmet_5x5x5.glb --coverage 0.02,0.05,0.1 --frames 10 --out $OUT/rays_$b > $OUT/rays_$b.log 2>&1)
    echo "== $b"; grep -E "^\| " $OUT/rays_$b/rays.md | cut -d'|' -f2-8
  done
  cd $OUT && tar czf results.tgz rays_* && rm -rf rays_prev rays_new
elif [ "$PART" = 2 ]; then
  $NEW bench scale --frames 10 --out $OUT/scale > $OUT/scale.log 2>&1; echo "exit $?"
  tail -30 $OUT/scale.log
else
  for scene in "atrium --duplicate 3 --no-dedup" "atrium --duplicate 4 --no-dedup" "atrium --duplicate 5 --no-dedup"; do
    for mode in raster full-rt; do
      case "$scene" in *"duplicate 5"*) ;; *) [ $mode = full-rt ] && continue;; esac
      mkdir -p /tmp/empty_new && cd /tmp/empty_new
      echo "== $scene, $mode, new binary"
      $NEW render --scene $scene --mode $mode --backend compute --width 2560 --height 1440 --frames 60 --out /tmp/o.png 2>&1 | grep -vE "^(shadow|forward|gbuffer|tonemap|shade|resolve|trace|rt_|accel|culled|transient|wrote|graph|pass)"
      cd - >/dev/null
    done
  done 2>&1 | tee $OUT/static_scene_3.txt
  for k in 1 2; do
    $NEW bench build --scenes organic,atrium --max-factor 1 --backend compute --out $OUT/build_$k > $OUT/build_$k.log 2>&1
    echo "== build run $k"; grep -E "^\| (organic|atrium)" $OUT/build_$k/gpu_build.md
  done
  cd $OUT && tar czf results.tgz build_1 build_2 && rm -rf build_1 build_2
fi
