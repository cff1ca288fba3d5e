#!/bin/bash
# Many lights on the GPU machine, one binary (.gpu/raygraph.gz), built-in files (an empty
# folder): `render --graph G --scene atrium-lights --backend compute --width 2560 --height 1440
# --frames 20` for raster (1,024 unshadowed lights a pixel), hybrid and full RT with every light
# its own shadow ray (the graphs as they are), and hybrid and full RT with rt_shadow's
# `light_candidates` = 8 and 32 (one light a pixel picked by resampled importance sampling, in
# the shadow pass and at the reflection rays' hits; the graph files written beside, with
# `per_frame`). Then hybrid on the plain atrium (one sun)
# with light_candidates 8, against its own graph: what the picking costs where there is one
# light. Prints one line a run; the logs go to $OUT/many_lights.tgz.
set -u
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
gunzip -f .gpu/raygraph.gz; chmod +x .gpu/raygraph
ROOT=$PWD; OUT=${OUT:-/tmp/out}; mkdir -p $OUT/r /tmp/empty/graph
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
late() { [ $SECONDS -gt ${DEADLINE:-540} ] && echo "deadline: $1 skipped"; }
for g in hybrid full_rt; do
  for m in 8 32; do
    python3 - "$ROOT/graph/$g.ron" "/tmp/empty/graph/${g}_m$m.ron" $m <<'PY'
import sys
src, dst, m = sys.argv[1], sys.argv[2], sys.argv[3]
s = open(src).read()
a = '"material": "gbuffer.material", "lobes": "gbuffer.lobes", "tlas": "accel.tlas",\n            },\n        ),'
assert s.count(a) == 1, src
b = a[:-3] + '    params: {"light_candidates": %s, "per_frame": true},\n        ),' % m
s = s.replace(a, b)
r = 'params: {"bounces": 2},'
assert s.count(r) == 1, src
s = s.replace(r, 'params: {"bounces": 2, "light_candidates": %s, "per_frame": true},' % m)
open(dst, 'w').write(s)
PY
  done
done
frame() { local graph=$1 scene=$2 log=$3
  (cd /tmp/empty && timeout 120 $ROOT/.gpu/raygraph render --graph $graph --scene $scene --backend compute \
    --width 2560 --height 1440 --frames 20 --out $OUT/r/x.png > $log 2>&1) || tail -2 $log
  echo "$(basename $graph) $scene | $(grep -E '^total' $log | awk '{print "gpu", $3}') | $(grep -E '^shadow/shadow' $log | awk '{print "shadow", $3, "rays/px", $5}') | $(grep -E '^reflection/reflection' $log | awk '{print "reflection", $3}') | $(grep -E '^frame wall' $log | sed 's/.*: //')"
}
for graph in graph/raster.ron graph/hybrid.ron graph/hybrid_m8.ron graph/hybrid_m32.ron graph/full_rt.ron graph/full_rt_m8.ron graph/full_rt_m32.ron; do
  late "$graph" && break
  [ -e /tmp/empty/$graph ] || cp $ROOT/$graph /tmp/empty/$graph
  frame $graph atrium-lights $OUT/r/$(basename $graph .ron)_lights.log
done
for graph in graph/hybrid.ron graph/hybrid_m8.ron; do
  late "$graph atrium" && break
  frame $graph atrium $OUT/r/$(basename $graph .ron)_atrium.log
done
rm -f $OUT/r/*.png; cd $OUT && tar czf many_lights.tgz r && rm -rf r
