#!/bin/bash
# The frame's CPU time outside its passes (scene update + uniforms + submit), this build
# (.gpu/raygraph.xz) against the build measured on 2026-11-30 (.gpu/raygraph_a478cc7.xz,
# BENCHMARKS.md "The frame's CPU time outside its passes from 262k to 32.8M triangles"), the
# two alternating, three rounds, on the GPU machine: `render --mode M --scene atrium --backend
# compute --width 2560 --height 1440 --frames 60` for M = raster, hybrid, full-rt; and this
# build's `render --graph graph/ao.ron` with rt_ao and with rt_ao_four_lanes. One line a run
# (GPU ms of the passes | frame wall ms | the parts outside the passes); logs in
# $OUT/frame_cpu.tgz.
set -u
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
for b in raygraph raygraph_a478cc7; do xz -dc .gpu/$b.xz > /tmp/$b; chmod +x /tmp/$b; done
OUT=${OUT:-/tmp/out}; mkdir -p $OUT/f /tmp/empty
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
one() { local bin=$1 name=$2; shift 2; local log=$OUT/f/$name.log
  (cd /tmp/empty && timeout 60 /tmp/$bin render --scene atrium --backend compute --width 2560 --height 1440 --frames 60 --out /tmp/x.png "$@" > $log 2>&1) || tail -2 $log
  echo "$name | $(grep -E '^total' $log | awk '{print "gpu", $3}') | $(grep -E '^frame wall' $log | sed 's/.*: //') | $(grep -E '^outside' $log | sed 's/.*medians): //')"
}
for round in 1 2 3; do
  for mode in raster hybrid full-rt; do
    for bin in raygraph raygraph_a478cc7; do
      if [ $SECONDS -gt ${DEADLINE:-400} ]; then echo "deadline"; break 3; fi
      one $bin ${mode}_${bin}_$round --mode $mode
    done
  done
  for variant in rt_ao rt_ao_four_lanes; do
    one raygraph ao_${variant}_$round --graph graph/ao.ron --use-layer rt_ao=$variant
  done
done
cd $OUT && tar czf frame_cpu.tgz f && rm -rf f
