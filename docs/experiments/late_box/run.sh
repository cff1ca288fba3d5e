#!/bin/bash
# PERF.md step 40, kept: the root's box tested before the watertight test's rows are formed
# (trace_merged). On the GPU machine, one release binary (.gpu/raygraph.xz): the driver's
# statistics of the trace kernels before (`main`: the files of the commit before) and after
# (`late_box`: this checkout's), `raygraph selftest`, then `bench rays --frames 10` on this
# checkout, Table 3 and the real assets (the helmet, the pine and helmet_5x5x5 at their cameras
# and at 2%, 5%, 10% of the frame), both back-ends; last, Table 3 before, compute only.
# Made by `bash docs/experiments/low_coverage/pack.sh 9a7ce72 docs/experiments/planes_rows
# late_box`. Results in $OUT/late_box.tgz.
. docs/experiments/low_coverage/preamble.sh
for v in main late_box; do
  kstats $v atrium --scene atrium --graph graph/bench_rays.ron
  kstats $v primary --scene atrium --graph graph/bench_primary.ron
done
timeout 150 $RG selftest > $OUT/r/selftest.log 2>&1; echo "selftest exit $?"
grep -E "passed|failed|not applicable" $OUT/r/selftest.log | tail -3
$RG scene export $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb /tmp/helmet_5x5x5.glb --duplicate 5 --no-dedup > /dev/null
for what in table3 real; do
  args=""
  [ $what = real ] && args="--scenes $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb,$ROOT/assets/gltf/smallpine/scene.gltf,/tmp/helmet_5x5x5.glb --coverage 0.02,0.05,0.1"
  timeout 240 $RG bench rays $args --frames 10 --out $OUT/r/$what > $OUT/r/$what.log 2>&1 || tail -2 $OUT/r/$what.log
  echo "== $what ($SECONDS s)"; grep -E "^\| " $OUT/r/$what/rays.md | grep -v -- "---" | grep -v " test |" | awk -F'|' '{print $2 "|" $3 "|" $5 "|" $6}' | sed 's|/[^ ]*/||'
done
bench main table3
cd $OUT && tar czf late_box.tgz r && rm -rf r
