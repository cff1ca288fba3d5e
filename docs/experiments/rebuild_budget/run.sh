#!/bin/bash
# The GPU rebuild against its budget (kernels <= 0.45 ms on the atrium), on the GPU machine, one
# session: first the builder's release test binary (.gpu/gpu_build_test: the radix sort against
# a stable CPU sort with one to four passes at every tile size, every tree checked node by node,
# H-PLOC's tree the same in eight builds); then `bench build --scenes organic,atrium
# --max-factor 1` with the checkout's build (.gpu/raygraph: H-PLOC's search radius 4; from
# f2c41d3 on, the layout's offsets a walk per triangle), the same
# with 24-bit Morton codes (RAYGRAPH_GPU_BUILD_MORTON_BITS=24: three sort passes) and the build
# before (.gpu/raygraph-old, a08df97: radius 8), in turn, twice each. The gpu_build.md rows are
# printed last, results in $OUT/results.tgz.
set -u
SPECS='radius4|raygraph|X=1 morton24|raygraph|RAYGRAPH_GPU_BUILD_MORTON_BITS=24 old|raygraph-old|X=1' \
  bash docs/experiments/sort_lookback/run.sh
