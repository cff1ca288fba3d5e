#!/bin/bash
# Main with the net as the AO default and the tree optimised by reinsertion, on the GPU machine:
# `raygraph selftest` (hard cases, agreement and the f64 reference channels on every back-end
# the adapter has, on the reinserted trees), then `bench rays --frames 10`: Table 3 and the
# real assets (the helmet, the pine, helmet_5x5x5 at their cameras and at 2%, 5%, 10% of the
# frame), both back-ends. One release binary (.gpu/raygraph.xz), this checkout's files.
# Results in $OUT/net_reinsert.tgz. Reused by later runs: NAME names the results, EXTRA the
# scenes after the helmet and the pine ("" for none).
set -u
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
xz -dc .gpu/raygraph.xz > .gpu/raygraph; chmod +x .gpu/raygraph
RG=$PWD/.gpu/raygraph; ROOT=$PWD; OUT=${OUT:-/tmp/out}; mkdir -p $OUT/r
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
timeout 150 $RG selftest > $OUT/r/selftest.log 2>&1; echo "selftest exit $?"; grep -E "passed|failed|not applicable" $OUT/r/selftest.log | tail -20
NAME=${NAME:-net_reinsert}; EXTRA=${EXTRA-,/tmp/helmet_5x5x5.glb}
[ -n "$EXTRA" ] && $RG scene export $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb /tmp/helmet_5x5x5.glb --duplicate 5 --no-dedup > /dev/null
REAL="--scenes $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb,$ROOT/assets/gltf/smallpine/scene.gltf$EXTRA --coverage 0.02,0.05,0.1"
for what in table3 real; do
  args=""; [ "$what" = real ] && args="$REAL"
  if [ $SECONDS -gt ${DEADLINE:-330} ]; then echo "deadline: $what skipped"; continue; fi
  timeout 220 $RG bench rays $args --frames 10 --out $OUT/r/$what > $OUT/r/$what.log 2>&1 || tail -2 $OUT/r/$what.log
  echo "== $what ($SECONDS s)"; grep -E "^\| " $OUT/r/$what/rays.md | grep -v -- "---" | grep -v " test |" | awk -F'|' '{print $2 "|" $3 "|" $5 "|" $6 "|" $(NF-1)}' | sed 's|/[^ ]*/||'
done
cd $OUT && tar czf $NAME.tgz r && rm -rf r
