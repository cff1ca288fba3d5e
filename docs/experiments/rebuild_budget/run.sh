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
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
for f in .gpu/*.xz; do xz -dc $f > ${f%.xz}; done; chmod +x .gpu/raygraph* .gpu/gpu_build_test
RG=$PWD/.gpu/raygraph; ROOT=$PWD
OUT=${OUT:-/tmp/out}; mkdir -p $OUT/runs
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
# The test binary finds the repository at the path it was built in.
mkdir -p /work && ln -sfn $ROOT /work/main
(cd $ROOT && timeout 200 .gpu/gpu_build_test --test-threads 1 > $OUT/runs/tests.log 2>&1); echo "tests exit $?"; grep -E "^test |test result" $OUT/runs/tests.log
(cd $ROOT && $RG bench rays --scenes box --backend compute --frames 5 --out /tmp/warm 2>&1 | grep -iE "adapter" | head -1)
for k in 1 2; do
  for spec in "radius4|raygraph|X=1" "morton24|raygraph|RAYGRAPH_GPU_BUILD_MORTON_BITS=24" "old|raygraph-old|X=1"; do
    IFS='|' read -r name bin var <<< "$spec"
    if [ $SECONDS -gt 500 ]; then echo "skipped: ${name}_$k"; continue; fi
    (cd $ROOT && env $var timeout 150 .gpu/$bin bench build --scenes organic,atrium --max-factor 1 --out $OUT/runs/${name}_$k > $OUT/runs/${name}_$k.log 2>&1) || tail -3 $OUT/runs/${name}_$k.log
  done
done
head -3 $(ls $OUT/runs/*/gpu_build.md | head -1)
for d in $OUT/runs/*/; do n=$(basename $d); grep -E "^\| (organic|atrium)" $d/gpu_build.md | sed "s/^/$n /"; done
cd $OUT && tar czf results.tgz runs 2>/dev/null; rm -rf runs
