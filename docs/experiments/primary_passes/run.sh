#!/bin/bash
# PERF.md step 50 (diagnostic): how much of the pine's G-buffer primary pass at low coverage is
# the traversals a primary ray starts again past each BLEND surface or culled back face
# (common/primary_hit.wgsl's closest_visible: up to MAX_CULLED = 16 more). `no_pass`: none (a
# ray ends at its first hit, a BLEND one or a culled back face counting as a miss; its images
# differ). On the GPU machine, one release binary (.gpu/raygraph.xz): `bench rays --backend
# compute --frames 10` on the pine and the helmet at their cameras and at 2%, 5%, 10% of the
# frame, for main, no_pass and main again. Made by `bash docs/experiments/low_coverage/pack.sh
# REV docs/experiments/primary_passes no_pass`. Results in $OUT/primary_passes.tgz.
. docs/experiments/low_coverage/preamble.sh
for v in main no_pass main; do bench $v real; done
cd $OUT && tar czf primary_passes.tgz r && rm -rf r
