#!/bin/bash
# The radix sort's look-back, 32 tiles read at a time (the checkout, .gpu/raygraph), against one
# tile at a time (.gpu/raygraph-old, a08df97), on the GPU machine, one session: first the
# builder's release test binary (.gpu/gpu_build_test: the sort against a stable CPU sort at every
# tile size up to a million keys, every tree checked node by node, H-PLOC's tree the same in
# eight builds); then `bench build --scenes organic,atrium --max-factor 1` with each binary and,
# for comparing, the new one with H-PLOC's search radius at 6 and 4
# (RAYGRAPH_GPU_BUILD_RADIUS; 8 is the default), in turn, twice each. The gpu_build.md rows are
# printed last, results in $OUT/results.tgz. SPECS ("name|binary under .gpu/|VAR=value" ...)
# replaces the builds compared (docs/experiments/rebuild_budget/run.sh).
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
  for spec in ${SPECS:-"window|raygraph|X=1" "old|raygraph-old|X=1" "radius6|raygraph|RAYGRAPH_GPU_BUILD_RADIUS=6" "radius4|raygraph|RAYGRAPH_GPU_BUILD_RADIUS=4"}; do
    IFS='|' read -r name bin var <<< "$spec"
    if [ $SECONDS -gt 500 ]; then echo "skipped: ${name}_$k"; continue; fi
    (cd $ROOT && env $var timeout 150 .gpu/$bin bench build --scenes organic,atrium --max-factor 1 --out $OUT/runs/${name}_$k > $OUT/runs/${name}_$k.log 2>&1) || tail -3 $OUT/runs/${name}_$k.log
  done
done
head -3 $(ls $OUT/runs/*/gpu_build.md | head -1)
for d in $OUT/runs/*/; do n=$(basename $d); grep -E "^\| (organic|atrium)" $d/gpu_build.md | sed "s/^/$n /"; done
cd $OUT && tar czf results.tgz runs 2>/dev/null; rm -rf runs
