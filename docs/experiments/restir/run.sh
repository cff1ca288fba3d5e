#!/bin/bash
# ReSTIR DI on the GPU machine, one release binary (.gpu/raygraph.gz), run in the checkout (its
# graph, layers and shaders): `bench lights` on atrium-lights at 1280x720 on `compute` (every
# light, resampling from M = 1..64, ReSTIR DI; the path-traced reference 16 paths a pixel and
# frame over 256 frames, its light picked from 8 candidates), then `render --frames 60` at
# 2560x1440 of graph/hybrid_restir.ron (and `bench lights` on the helmet under the studio map) and of graph/hybrid.ron with `light_candidates` 8 (the
# graph written to /tmp, the same edit as docs/experiments/many_lights/run.sh) for their passes'
# GPU ms. Results in $OUT/restir.tgz; the tables printed last.
set -u
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
gunzip -f .gpu/raygraph.gz; chmod +x .gpu/raygraph
ROOT=$PWD; RG=$ROOT/.gpu/raygraph; OUT=${OUT:-/tmp/out}; mkdir -p $OUT/r
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
timeout 400 $RG bench lights --scenes atrium-lights --backend compute --reference-frames 256 --out $OUT/r/lights > $OUT/r/lights.log 2>&1 || tail -3 $OUT/r/lights.log
# The helmet under the studio map (no punctual light: the map replaces the sun), the map among
# ReSTIR DI's sources.
timeout 200 $RG bench lights --scenes helmet=assets/gltf/DamagedHelmet/DamagedHelmet.glb --env assets/env/studio_small_03_1k.hdr --candidates 1,8,64 --backend compute --reference-frames 256 --out $OUT/r/lights_env > $OUT/r/lights_env.log 2>&1 || tail -3 $OUT/r/lights_env.log
python3 - "$ROOT/graph/hybrid.ron" /tmp/hybrid_m8.ron <<'PY'
import sys
s = open(sys.argv[1]).read()
a = '"material": "gbuffer.material", "lobes": "gbuffer.lobes", "tlas": "accel.tlas",\n            },\n        ),'
assert s.count(a) == 1
s = s.replace(a, a[:-3] + '    params: {"light_candidates": 8, "per_frame": true},\n        ),')
r = 'params: {"bounces": 2},'
assert s.count(r) == 1
s = s.replace(r, 'params: {"bounces": 2, "light_candidates": 8, "per_frame": true},')
open(sys.argv[2], 'w').write(s)
PY
cp /tmp/hybrid_m8.ron graph/hybrid_m8.ron
for g in graph/hybrid_restir.ron graph/hybrid_m8.ron graph/hybrid_restir.ron graph/hybrid_m8.ron; do
  if [ $SECONDS -gt ${DEADLINE:-540} ]; then echo "deadline: $g skipped"; continue; fi
  log=$OUT/r/$(basename $g .ron)_$SECONDS.log
  timeout 100 $RG render --graph $g --scene atrium-lights --backend compute --width 2560 --height 1440 --frames 60 --out $OUT/r/x.png > $log 2>&1 || tail -2 $log
  echo "== $g"; grep -E "^(total|direct/|shadow/|reflection/|frame wall|ao/|gbuffer/|resolve/)" $log
done
rm -f graph/hybrid_m8.ron
cat $OUT/r/lights/lights.md $OUT/r/lights_env/lights.md
rm -f $OUT/r/lights_env/*.png
# The images but the reference's, every light's, resampling from 64 and ReSTIR DI's stay behind (size).
rm -f $OUT/r/x.png
cd $OUT/r/lights && ls *.png | grep -vE '^atrium-lights_(reference|every_light|resampling_from_64|ReSTIR_DI)(_flip)?\.png$' | xargs rm -f
cd $OUT && tar czf restir.tgz r 2>/dev/null; rm -rf r
