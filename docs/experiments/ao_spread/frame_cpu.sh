#!/bin/bash
# The frame's CPU time outside the passes with the AO list pass (rt_ao) against the four-lane
# schedule (rt_ao_four_lanes, one dispatch fewer), one binary (.gpu/raygraph), built-in files
# (an empty folder): `render --graph G --scene atrium --backend compute --width 2560 --height
# 1440 --frames 60 [--use-layer rt_ao=rt_ao_four_lanes]` for G = ao, hybrid, hybrid_denoised,
# full_rt, raster, alternating, two rounds; then `bench build --scenes atrium --max-factor 1`
# twice (the GPU rebuild's kernels and the cache rebuild's wall time). Prints one line a run.
set -u
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
gunzip -f .gpu/raygraph.gz; chmod +x .gpu/raygraph
RG=$PWD/.gpu/raygraph; OUT=${OUT:-/tmp/out}; mkdir -p $OUT/r /tmp/empty
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
one() { local graph=$1 variant=$2 log=$3 use=""
  [ "$variant" = four_lanes ] && use="--use-layer rt_ao=rt_ao_four_lanes"
  (cd /tmp/empty && timeout 90 $RG render --graph graph/$graph.ron --scene atrium --backend compute $use \
    --width 2560 --height 1440 --frames 60 --out $OUT/r/x.png > $log 2>&1) || tail -2 $log
  echo "$graph $variant | $(grep -E '^total' $log | awk '{print "gpu", $3}') | $(grep -E '^frame wall' $log | sed 's/.*: //') | $(grep -E '^outside' $log | sed 's/.*medians): //')"
}
for round in 1 2; do
  for graph in ao hybrid hybrid_denoised full_rt raster; do
    for variant in rt_ao four_lanes; do
      if [ $SECONDS -gt ${DEADLINE:-300} ]; then echo "deadline: round $round stopped"; break 3; fi
      one $graph $variant $OUT/r/${graph}_${variant}_$round.log
    done
  done
done
for k in 1 2; do
  if [ $SECONDS -gt ${DEADLINE:-300} ]; then echo "deadline: bench build $k skipped"; break; fi
  (cd /tmp/empty && timeout 120 $RG bench build --scenes atrium --max-factor 1 --out $OUT/r/build_$k > $OUT/r/build_$k.log 2>&1) || tail -2 $OUT/r/build_$k.log
  grep -E "^\| atrium" $OUT/r/build_$k/*.md | head -3 | cut -c1-220
done
rm -f $OUT/r/*.png; cd $OUT && tar czf frame_cpu.tgz r && rm -rf r
