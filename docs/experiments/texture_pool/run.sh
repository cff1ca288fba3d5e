#!/bin/bash
# What a frame costs per scene texture on the CPU, before and after the textures were pooled
# (src/scene/texture_pool.rs: one 2D array per texture size and encoding instead of one binding
# array element per texture). Two release binaries in one call: .gpu/raygraph-before (dec628a)
# and .gpu/raygraph (the change), each with its built-in graphs, layers and shaders (an empty
# folder). Scenes: 64 and 1024 textured quads (many_textures.py: sizes 64-512), the helmet and
# the pine; graphs: hybrid, raster, hybrid_denoised; `render --frames 60 --width 2560 --height
# 1440 --backend compute`, before and after alternating, rounds until the deadline. Prints per
# run the CPU time outside the passes by part, the passes' GPU ms and the frame's wall ms.
set -u
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
gunzip -f .gpu/*.gz && chmod +x .gpu/raygraph*
ROOT=$PWD; OUT=${OUT:-/tmp/out}; mkdir -p $OUT/r /tmp/empty
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
python3 docs/experiments/texture_pool/many_textures.py 64 /tmp/tex64.gltf
python3 docs/experiments/texture_pool/many_textures.py 1024 /tmp/tex1024.gltf
declare -A SCENE=([tex64]=/tmp/tex64.gltf [tex1024]=/tmp/tex1024.gltf
  [helmet]=$ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb [pine]=$ROOT/assets/gltf/smallpine/scene.gltf)
one() { local bin=$1 scene=$2 graph=$3 log=$4
  (cd /tmp/empty && timeout 60 $ROOT/.gpu/$bin render --graph graph/$graph.ron --scene ${SCENE[$scene]} --backend compute \
    --width 2560 --height 1440 --frames 60 --out $OUT/r/$scene.png > $log 2>&1) || tail -2 $log
  echo "$bin $scene $graph | $(grep -E '^total' $log | awk '{print "gpu", $3}') | $(grep -E '^frame wall' $log | sed 's/.*: //') | $(grep -E '^outside' $log | sed 's/.*medians): //')"
}
for round in 1 2 3; do
  for scene in tex1024 tex64 helmet pine; do
    for graph in hybrid raster hybrid_denoised; do
      for bin in raygraph-before raygraph; do
        if [ $SECONDS -gt 520 ]; then echo "deadline: round $round stopped"; break 4; fi
        one $bin $scene $graph $OUT/r/${bin}_${scene}_${graph}_$round.log
      done
    done
  done
done
rm -f $OUT/r/*.png; cd $OUT && tar czf results.tgz r && rm -rf r
