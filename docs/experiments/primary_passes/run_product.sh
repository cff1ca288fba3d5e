#!/bin/bash
# PERF.md step 51: primary rays that pass BLEND surfaces in one traversal (TRACE_PASS_BLEND).
# On the GPU machine, one release binary (.gpu/raygraph.xz) and this checkout as it is:
# `raygraph selftest`, then `bench rays --frames 10` on both back-ends on the real assets (the
# helmet, the pine and helmet_5x5x5 at their cameras and at 2%, 5%, 10% of the frame; Table 3's
# scenes have no BLEND material, so the flag is a constant zero there and they are left out).
# .gpu/diag.tgz is unpacked but not used. Results in $OUT/pass_blend.tgz.
. docs/experiments/low_coverage/preamble.sh
timeout 150 $RG selftest > $OUT/r/selftest.log 2>&1; echo "selftest exit $?"
grep -E "passed|failed|not applicable" $OUT/r/selftest.log | tail -3
$RG scene export $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb /tmp/helmet_5x5x5.glb --duplicate 5 --no-dedup > /dev/null
A=$ROOT/assets/gltf
timeout 240 $RG bench rays --scenes $A/DamagedHelmet/DamagedHelmet.glb,$A/smallpine/scene.gltf,/tmp/helmet_5x5x5.glb --coverage 0.02,0.05,0.1 --frames 10 --out $OUT/r/real > $OUT/r/real.log 2>&1 || tail -2 $OUT/r/real.log
grep -E "^\| " $OUT/r/real/rays.md | grep -v -- "---" | grep -v " test |" | awk -F'|' '{print $2 "|" $3 "|" $5 "|" $6}' | sed 's|/[^ ]*/||'
cd $OUT && tar czf pass_blend.tgz r && rm -rf r
