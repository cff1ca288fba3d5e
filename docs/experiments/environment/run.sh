#!/bin/bash
# What environment-map lighting costs, and what scenes without a map pay for it: two binaries
# (.gpu/raygraph-before.gz: 1006bc8, before environment maps; .gpu/raygraph.gz: with them),
# built-in files (an empty folder).
# 1. `bench rays --frames 10` (Table 3's rows, both back-ends) with each binary.
# 2. `render --graph G --scene atrium --backend compute --width 2560 --height 1440 --frames 60`
#    for G = raster, hybrid, full_rt, hybrid_denoised, alternating the binaries, two rounds:
#    the passes' GPU ms and the CPU time outside them.
# 3. The new binary with `--env assets/env/spiaggia_di_mondello_1k.hdr` on the same renders
#    (the map's cost), and on the helmet.
# Prints one line a run; the logs go to $OUT/environment.tgz.
set -u
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
for b in raygraph raygraph-before; do gunzip -f .gpu/$b.gz; chmod +x .gpu/$b; done
ROOT=$PWD; OUT=${OUT:-/tmp/out}; mkdir -p $OUT/r /tmp/empty
ENV=$ROOT/assets/env/spiaggia_di_mondello_1k.hdr
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
late() { [ $SECONDS -gt ${DEADLINE:-540} ] && echo "deadline: $1 skipped"; }
frame() { local bin=$1 graph=$2 scene=$3 log=$4; shift 4
  (cd /tmp/empty && timeout 90 $ROOT/.gpu/$bin render --graph graph/$graph.ron --scene $scene --backend compute \
    --width 2560 --height 1440 --frames 60 --out $OUT/r/x.png "$@" > $log 2>&1) || tail -2 $log
  echo "$bin $graph $scene $* | $(grep -E '^total' $log | awk '{print "gpu", $3}') | $(grep -E '^frame wall' $log | sed 's/.*: //') | $(grep -E '^outside' $log | sed 's/.*medians): //')"
}
for bin in raygraph-before raygraph; do
  late "bench rays $bin" && break
  (cd /tmp/empty && timeout 200 $ROOT/.gpu/$bin bench rays --frames 10 --out $OUT/r/rays_$bin > $OUT/r/rays_$bin.log 2>&1) || tail -2 $OUT/r/rays_$bin.log
  echo "== bench rays, $bin"; grep -E "^\| " $OUT/r/rays_$bin/rays.md | grep -v -- "---" | cut -d'|' -f2-5,7,8
done
for round in 1 2; do
  for graph in raster hybrid full_rt hybrid_denoised; do
    for bin in raygraph-before raygraph; do
      late "round $round $graph $bin" && break 3
      frame $bin $graph atrium $OUT/r/${graph}_${bin}_$round.log
    done
  done
done
for graph in raster hybrid full_rt; do
  late "env $graph" && break
  frame raygraph $graph atrium $OUT/r/${graph}_env.log --env $ENV
  frame raygraph $graph $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb $OUT/r/${graph}_helmet.log
  frame raygraph $graph $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb $OUT/r/${graph}_helmet_env.log --env $ENV
done
rm -f $OUT/r/*.png; cd $OUT && tar czf environment.tgz r && rm -rf r
