#!/bin/bash
# `bench anim` on the H100 (BENCHMARKS.md, "Animation"): organic-skinned (250,880 skinned
# triangles, deformed on the GPU) and atrium-moving (the atrium with 200 moving instances) at
# 1920x1080, one 4-second loop at 60 frames per second, on the compute back-end under the auto
# policy at four thresholds, always refit and always rebuild; then the rt-pipeline back-end
# (NVIDIA's own builder, a rebuild every frame) on the same scenes for comparison.
# Run on the device machine with carry [".gpu"] (the release binary in .gpu/raygraph).
for f in .gpu/gl/*.deb; do dpkg -x $f /; done; ldconfig
R=$PWD/.gpu/raygraph
$R bench anim --scenes organic-skinned,atrium-moving --frames 240 --max-growth 1.1,1.25,1.5,2 --out $OUT/compute >/tmp/compute.log 2>&1 || tail -5 /tmp/compute.log
$R bench anim --scenes organic-skinned,atrium-moving --frames 120 --backend rt-pipeline --out /tmp/rtp >/tmp/rtp.log 2>&1 || tail -5 /tmp/rtp.log
mkdir -p $OUT/rt-pipeline && cp /tmp/rtp/anim.md /tmp/rtp/anim.csv $OUT/rt-pipeline/ 2>/dev/null
head -3 /tmp/compute.log
grep "^|" $OUT/compute/anim.md | cut -d'|' -f2-13
grep "^|" $OUT/rt-pipeline/anim.md | cut -d'|' -f2-13
