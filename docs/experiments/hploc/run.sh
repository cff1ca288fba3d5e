#!/bin/bash
# H-PLOC against the PLOC rounds (src/accel/gpu_build.rs, shaders/accel/hploc.wgsl), one release
# binary, one session: first the builder's tests on this GPU (the release test binary
# .gpu/gpu_build_test: every tree checked node by node, the atrium's hits against the CPU
# build's, and H-PLOC's tree the same in eight builds of one input, which a record read before
# it was visible would break); then `bench build --scenes organic,atrium --max-factor 1` with
# H-PLOC (the default) and with `RAYGRAPH_GPU_BUILD=ploc`, alternating, twice each, after a
# warm-up; then the atrium copied 2x2x2 (2.1M triangles) with each. The gpu_build.md rows are
# printed last, results in $OUT/results.tgz.
#   `run.sh teams`: the same tests, then the same bench with the four-team H-PLOC (the default,
#   .gpu/raygraph), an eight-team build of it (.gpu/raygraph-t8: HPLOC_TEAMS = 8, workgroups of
#   256) and the PLOC rounds, in turn, twice each (the one-team version of the first part is
#   compared through the PLOC rows of each run: with it, the call was past the 64 MiB a call
#   carries).
#   `run.sh t1`: the four-team H-PLOC against a one-team build of the same code (.gpu/raygraph-t1:
#   HPLOC_TEAMS = 1, workgroups of 32) and the PLOC rounds, in turn, twice each.
#   `run.sh ids`: a round's node ids taken by one atomic per team (the checkout, .gpu/raygraph)
#   against one atomic per node (.gpu/raygraph-t1, the t1 part's one-team build) and the PLOC
#   rounds, in turn, twice each; then `bench scale --steps atrium:2,atrium:3 --backend compute
#   --frames 5` (2.1M and 7.1M unique triangles) with H-PLOC and with the PLOC rounds.
#   `run.sh fence`: a probe, not a builder: the shipped H-PLOC (.gpu/raygraph, the code of
#   a26bb13) against a build of it whose two device-scope storage barriers are workgroup
#   barriers (.gpu/raygraph-nofence; without them a record may be read before it is visible,
#   so its trees are not to be trusted), to see what the barriers cost. No test binary.
set -u
PART=${1:-first}
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
gunzip -f .gpu/*.gz && chmod +x .gpu/raygraph* .gpu/gpu_build_test 2>/dev/null
RG=$PWD/.gpu/raygraph; ROOT=$PWD
OUT=${OUT:-/tmp/out}; mkdir -p $OUT/runs
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
# The test binary finds the repository at the path it was built in.
mkdir -p /work && ln -sfn $ROOT /work/main
if [ -x .gpu/gpu_build_test ]; then
  (cd $ROOT && timeout 150 .gpu/gpu_build_test --test-threads 1 > $OUT/runs/tests.log 2>&1); echo "tests exit $?"; grep -E "^test |SAH|test result" $OUT/runs/tests.log
fi
(cd $ROOT && $RG bench rays --scenes box --backend compute --frames 5 --out /tmp/warm 2>&1 | grep -iE "adapter" | head -1)
run() { # name max-factor scenes env...
  local name=$1 factor=$2 scenes=$3; shift 3
  if [ $SECONDS -gt 480 ]; then echo "skipped: $name"; return; fi
  (cd $ROOT && env "$@" timeout 150 ${BIN:-$RG} bench build --scenes $scenes --max-factor $factor --out $OUT/runs/$name > $OUT/runs/$name.log 2>&1) || tail -3 $OUT/runs/$name.log
}
# Each spec "name|binary under .gpu/ (empty: the checkout's)|environment (empty: none)", in
# turn, twice: runs name_1, name_2 of `bench build --scenes organic,atrium --max-factor 1`.
alternate() {
  for k in 1 2; do
    for spec in "$@"; do
      IFS='|' read -r name bin var <<< "$spec"
      BIN=${bin:+$ROOT/.gpu/$bin} run ${name}_$k 1 organic,atrium ${var:-X=1}
    done
  done
}
PLOC="ploc||RAYGRAPH_GPU_BUILD=ploc"
if [ "$PART" = fence ]; then
  alternate "shipped||" "nofence|raygraph-nofence|"
elif [ "$PART" = ids ]; then
  alternate "ids||" "t1|raygraph-t1|" "$PLOC"
  for b in hploc ploc; do
    if [ $SECONDS -gt 400 ]; then echo "skipped: scale $b"; continue; fi
    v=X=1; [ $b = ploc ] && v=RAYGRAPH_GPU_BUILD=ploc
    (cd $ROOT && env $v timeout 100 $RG bench scale --steps atrium:2,atrium:3 --backend compute --frames 5 --out $OUT/runs/scale_$b > $OUT/runs/scale_$b.log 2>&1) || tail -3 $OUT/runs/scale_$b.log
    grep -E "^\| atrium" $OUT/runs/scale_$b/scale.md | sed "s/^/scale_$b /"
  done
elif [ "$PART" = t1 ]; then
  alternate "team1|raygraph-t1|" "teams4||" "$PLOC"
elif [ "$PART" = teams ]; then
  alternate "teams4||" "teams8|raygraph-t8|" "$PLOC"
else
  alternate "hploc||" "$PLOC"
  run hploc_x2 2 atrium X=1
  run ploc_x2 2 atrium RAYGRAPH_GPU_BUILD=ploc
fi
head -3 $(ls $OUT/runs/*/gpu_build.md | head -1)
for d in $OUT/runs/*/; do n=$(basename $d); grep -E "^\| (organic|atrium)" $d/gpu_build.md | sed "s/^/$n /"; done
cd $OUT && tar czf results.tgz runs 2>/dev/null; rm -rf runs
