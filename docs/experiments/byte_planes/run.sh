#!/bin/bash
# PERF.md step 46: what the decoding of an 8-bit quantised child (a compressed wide node's six
# planes, Ylitie, Karras and Laine 2017) adds to the exact step, before building such a node:
# `byte_planes` (each byte converted to an f32) and `byte_magic` (each byte placed in the
# mantissa of 2^23, 2^23 subtracted), both on the exact nodes' words through a mask zero at run
# time, so their images are main's. On the GPU machine, one release binary (.gpu/raygraph.xz):
# the driver's statistics of the atrium's trace kernels for the three; Table 3, compute only,
# main, byte_planes, byte_magic, main; then this checkout as it is: `raygraph selftest` and
# `bench rays --frames 10`, both back-ends, Table 3 and the real assets (the helmet, the pine and
# helmet_5x5x5 at their cameras and at 2%, 5%, 10% of the frame). Made by `bash
# docs/experiments/low_coverage/pack.sh REV docs/experiments/byte_planes byte_planes
# byte_magic`. Results in $OUT/byte_planes.tgz.
. docs/experiments/low_coverage/preamble.sh
for v in main byte_planes byte_magic; do
  kstats $v atrium --scene atrium --graph graph/bench_rays.ron
done
for v in main byte_planes byte_magic main; do bench $v table3; done
shipped
cd $OUT && tar czf byte_planes.tgz r && rm -rf r
