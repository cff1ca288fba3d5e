#!/bin/bash
# helmet_5x5x5 (1.93M triangles) at its camera and at 2%, 5%, 10% of the frame, both back-ends,
# with the warm-up's first frame (the CPU tree's build) before the clock pump; nvidia-smi's SM
# clock sampled every 200 ms beside it. Results in $OUT/h5.tgz.
set -u
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
xz -dc .gpu/raygraph.xz > .gpu/raygraph; chmod +x .gpu/raygraph
RG=$PWD/.gpu/raygraph; ROOT=$PWD; OUT=${OUT:-/tmp/out}; mkdir -p $OUT/r
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
$RG scene export $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb /tmp/helmet_5x5x5.glb --duplicate 5 --no-dedup > /dev/null
nvidia-smi --query-gpu=timestamp,clocks.sm --format=csv,noheader -lms 200 > $OUT/r/clocks.csv &
timeout 220 $RG bench rays --scenes /tmp/helmet_5x5x5.glb --coverage 0.02,0.05,0.1 --frames 10 --out $OUT/r/h5 > $OUT/r/h5.log 2>&1 || tail -2 $OUT/r/h5.log
kill %1
grep -E "^\| " $OUT/r/h5/rays.md | grep -v -- "---" | grep -v " test |" | awk -F'|' '{print $2 "|" $3 "|" $5 "|" $6 "|" $(NF-1)}' | sed 's|/[^ ]*/||'
cd $OUT && tar czf h5.tgz r && rm -rf r
