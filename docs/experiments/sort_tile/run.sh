#!/bin/bash
# The radix sort's tile size (src/accel/radix_sort.rs, RAYGRAPH_SORT_TILE), one release binary,
# one session: first the builder's tests on this GPU (.gpu/gpu_build_test: the sort against a
# stable CPU sort at every tile size, every tree checked node by node), then after a warm-up
# `bench build --scenes organic,atrium --max-factor 1` with tiles of 2048 (the default), 1024,
# 512 and 256 keys, in turn, twice each. The gpu_build.md rows are printed last, results in
# $OUT/results.tgz. `TILES="2048 4096" run.sh`: those tiles instead.
set -u
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
gunzip -f .gpu/*.gz && chmod +x .gpu/raygraph* .gpu/gpu_build_test 2>/dev/null
RG=$PWD/.gpu/raygraph; ROOT=$PWD
OUT=${OUT:-/tmp/out}; mkdir -p $OUT/runs
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
# The test binary finds the repository at the path it was built in.
mkdir -p /work && ln -sfn $ROOT /work/main
if [ -x .gpu/gpu_build_test ]; then
  (cd $ROOT && timeout 150 .gpu/gpu_build_test --test-threads 1 > $OUT/runs/tests.log 2>&1); echo "tests exit $?"; grep -E "^test |test result" $OUT/runs/tests.log
fi
(cd $ROOT && $RG bench rays --scenes box --backend compute --frames 5 --out /tmp/warm 2>&1 | grep -iE "adapter" | head -1)
for k in 1 2; do
  for tile in ${TILES:-2048 1024 512 256}; do
    name=tile${tile}_$k
    if [ $SECONDS -gt ${DEADLINE:-420} ]; then echo "skipped: $name"; continue; fi
    (cd $ROOT && RAYGRAPH_SORT_TILE=$tile timeout 150 $RG bench build --scenes organic,atrium --max-factor 1 --out $OUT/runs/$name > $OUT/runs/$name.log 2>&1) || tail -3 $OUT/runs/$name.log
  done
done
head -3 $(ls $OUT/runs/*/gpu_build.md | head -1)
for d in $OUT/runs/*/; do n=$(basename $d); grep -E "^\| (organic|atrium)" $d/gpu_build.md | sed "s/^/$n /"; done
cd $OUT && tar czf results.tgz runs 2>/dev/null; rm -rf runs
