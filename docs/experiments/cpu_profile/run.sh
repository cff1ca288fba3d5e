#!/bin/bash
# Where the frame's CPU time goes on the GPU machine: a release binary built with a sampling
# profiler (pprof, SIGPROF at 2 kHz, written as folded stacks to $RAYGRAPH_PPROF) around the
# timed frames of `render`. The profiling build is pprof.patch beside this script, applied to
# abf9c61 (pprof is not a dependency of raygraph) and built with
# RUSTFLAGS="-C force-frame-pointers=yes" CARGO_PROFILE_RELEASE_DEBUG=line-tables-only, its
# debug info stripped (strip --strip-debug), gzipped to .gpu/rgprof.gz. The folded stacks and
# render logs land in $OUT/cpu_profile.tgz.
set -u
for f in .gpu/gl/*.deb; do dpkg -x $f /; done; ldconfig
gunzip -c .gpu/rgprof.gz > /tmp/rg && chmod +x /tmp/rg
mkdir -p /tmp/p
nvidia-smi --query-gpu=name,clocks.sm --format=csv,noheader
run() { # name, args...
  local name=$1; shift
  # Small frames, many of them: the CPU's part of a frame does not depend on its size.
  RAYGRAPH_PPROF=/tmp/p/$name.folded /tmp/rg render "$@" --backend compute --width 256 --frames ${FRAMES:-6000} --out /tmp/x.png > /tmp/p/$name.log 2>&1
  grep -E "^adapter|outside|wall" /tmp/p/$name.log
}
run raster_lights --mode raster --scene atrium-lights
run raster_atrium --mode raster --scene atrium
run hybrid_atrium --mode hybrid --scene atrium
run denoised_atrium --graph graph/hybrid_denoised.ron --scene atrium
run fullrt_atrium --mode full-rt --scene atrium
tar czf $OUT/cpu_profile.tgz -C /tmp p
