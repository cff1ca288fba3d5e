#!/bin/bash
# What emissive triangles as lights cost, and what scenes without them pay: two binaries
# (.gpu/raygraph-before.gz: b5fff26, before; .gpu/raygraph.gz: with them), built-in files (an
# empty folder).
# 1. `bench rays --frames 10` (Table 3's rows, both back-ends) with each binary, then the
#    helmet and the pine (`--scenes`; graph/bench_rays.ron traces no emitter rays).
# 2. `render --graph G --scene atrium --backend compute --width 2560 --height 1440 --frames 60`
#    for G = raster, hybrid, full_rt, hybrid_denoised, alternating the binaries, two rounds:
#    the passes' GPU ms and the CPU time outside them (the atrium has no emitter).
# 3. The helmet (an emissive texture: its lit parts are lights) in hybrid, full_rt and
#    hybrid_denoised with each binary: what the shadow pass's 4 emitter rays a pixel cost.
# `run.sh rays` runs 1, `run.sh frames` 2 and 3 (one device call each). Prints one line a run;
# the logs go to $OUT/emitters_$1.tgz.
set -u
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
for b in raygraph raygraph-before; do gunzip -f .gpu/$b.gz; chmod +x .gpu/$b; done
ROOT=$PWD; OUT=${OUT:-/tmp/out}; mkdir -p $OUT/r /tmp/empty
HELMET=$ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb
PINE=$ROOT/assets/gltf/smallpine/scene.gltf
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
late() { [ $SECONDS -gt ${DEADLINE:-540} ] && echo "deadline: $1 skipped"; }
frame() { local bin=$1 graph=$2 scene=$3 log=$4; shift 4
  (cd /tmp/empty && timeout 90 $ROOT/.gpu/$bin render --graph graph/$graph.ron --scene $scene --backend compute \
    --width 2560 --height 1440 --frames 60 --out $OUT/r/x.png "$@" > $log 2>&1) || tail -2 $log
  echo "$bin $graph $(basename $scene) | $(grep -E '^total' $log | awk '{print "gpu", $3}') | $(grep -E '^frame wall' $log | sed 's/.*: //') | $(grep -E '^outside' $log | sed 's/.*medians): //')"
}
rays() { local bin=$1 name=$2; shift 2
  (cd /tmp/empty && timeout 200 $ROOT/.gpu/$bin bench rays --frames 10 --out $OUT/r/${name}_$bin "$@" > $OUT/r/${name}_$bin.log 2>&1) || tail -2 $OUT/r/${name}_$bin.log
  echo "== bench rays $name, $bin"; grep -E "^\| " $OUT/r/${name}_$bin/rays.md | grep -v -- "---" | cut -d'|' -f2-5,7,8
}
WHAT=${1:-frames}
[ "$WHAT" = rays ] && for bin in raygraph-before raygraph; do
  late "bench rays $bin" && break
  rays $bin table3
  rays $bin real --scenes $HELMET,$PINE
done
[ "$WHAT" = frames ] && for round in 1 2; do
  for graph in raster hybrid full_rt hybrid_denoised; do
    for bin in raygraph-before raygraph; do
      late "round $round $graph $bin" && break 3
      frame $bin $graph atrium $OUT/r/${graph}_${bin}_$round.log
    done
  done
done
[ "$WHAT" = frames ] && for graph in hybrid full_rt hybrid_denoised; do
  for bin in raygraph-before raygraph; do
    late "helmet $graph $bin" && break 2
    frame $bin $graph $HELMET $OUT/r/${graph}_helmet_$bin.log
  done
done
rm -f $OUT/r/*.png; cd $OUT && tar czf emitters_$WHAT.tgz r && rm -rf r
