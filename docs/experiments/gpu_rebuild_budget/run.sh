#!/bin/bash
# The GPU machine's run for issue 35, item 4 (the atrium's GPU rebuild: kernels <= 0.45 ms,
# cache rebuild <= 1.5 ms of wall time). Two release binaries in one call: .gpu/raygraph-base
# (before, 42c239d: bitonic sort, two dispatches per round, three waits per cache rebuild) and
# .gpu/raygraph (after), each from an empty folder of its own (release builds, gzipped; the
# Vulkan loader's packages in .gpu/gl/); the after binary also with the environment's variants
# (the old sort, the old two dispatches per round, rounds dispatched for all triangles, the old
# sort and rounds together, a larger local reduction), so every lever is compared in the same
# session. `bench build --scenes organic,atrium --max-factor 1` each; the gpu_build.md rows
# are printed last, results in $OUT/results.tgz.
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
gunzip -f .gpu/raygraph-base.gz .gpu/raygraph.gz; chmod +x .gpu/raygraph-base .gpu/raygraph
OLD=$PWD/.gpu/raygraph-base; NEW=$PWD/.gpu/raygraph
mkdir -p /tmp/run_old /tmp/run_new $OUT/runs
(cd /tmp/run_new && $NEW bench rays --scenes box --backend compute --frames 5 --out /tmp/warm 2>&1 | grep -iE "adapter" | head -1)
run() { # name binary env...
  local name=$1 bin=$2; shift 2
  (cd /tmp/run_new && env "$@" timeout 120 $bin bench build --scenes organic,atrium --max-factor 1 --out $OUT/runs/$name > $OUT/runs/$name.log 2>&1) || tail -3 $OUT/runs/$name.log
}
run base_1 $OLD X=1
run new_1 $NEW X=1
run new_bitonic_1 $NEW RAYGRAPH_GPU_BUILD_SORT=bitonic
run new_pair_1 $NEW RAYGRAPH_GPU_BUILD_ROUND=pair
run new_direct_1 $NEW RAYGRAPH_GPU_BUILD_INDIRECT=0
run new_old_kernels_1 $NEW RAYGRAPH_GPU_BUILD_SORT=bitonic RAYGRAPH_GPU_BUILD_ROUND=pair
run new_local128_1 $NEW RAYGRAPH_GPU_BUILD_LOCAL=128
run new_local64_1 $NEW RAYGRAPH_GPU_BUILD_LOCAL=64
run base_2 $OLD X=1
run new_2 $NEW X=1
echo "run | scene | triangles | GPU build ms (median) | (min) | sort / rounds / finish / layout ms | rounds | depth | wall ms build + read-back | cache rebuild wall ms | hash / update / arrays placed ms | CPU build ms | SAH GPU | SAH CPU | GPU/CPU"
for d in $OUT/runs/*/; do n=$(basename $d); grep -E "^\| (organic|atrium) " $d/gpu_build.md | sed "s/^/$n /"; done
cd $OUT && tar czf results.tgz runs 2>/dev/null; rm -rf runs
