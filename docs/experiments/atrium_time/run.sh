#!/bin/bash
# Where the atrium's scene-workload time goes (PERF.md, "Where the atrium's time goes"): one
# thing varied at a time on the atrium (`bench rays --scenes atrium --frames 10`, compute
# unless named), one binary, one session:
#   1. the AO ray's length: --ao-length 0, 0.0125, 0.025, 0.05 (Table 3's), 0.1, 0.2;
#   2. AO rays per pixel: --ao-rays 4, 16 (64 is row 1's 0.05);
#   3. rays per invocation: the AO schedules (`--use-layer rt_ao=rt_ao_compacted`: one
#      invocation per (pixel, lane) item; `rt_ao_persistent`: a fixed dispatch taking items off
#      a counter) against the default four lanes a pixel;
#   4. the driver (`--backend rt-pipeline`) at lengths 0 and 0.05.
# Each bench also runs Miss and Stress on the atrium. Results under $OUT (results.tgz); the
# AO pass's GPU ms and rays per pixel, and the frame's GR/s, printed last.
set -u
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
gunzip -f .gpu/raygraph.gz && chmod +x .gpu/raygraph
RG=$PWD/.gpu/raygraph
OUT=${OUT:-/tmp/out}; mkdir -p $OUT/r /tmp/run
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv,noheader
b() { local name=$1; shift
  # The device call's ten minutes: what is left after 8 of them is skipped (and named).
  if [ $SECONDS -gt 480 ]; then echo "skipped: $name $*"; return; fi
  (cd /tmp/run && timeout 100 $RG bench rays --scenes atrium --frames 10 "$@" --out $OUT/r/$name > $OUT/r/$name.log 2>&1) || tail -2 $OUT/r/$name.log; }
for l in 0 0.0125 0.025 0.05 0.1 0.2; do b len_$l --backend compute --ao-length $l; done
for n in 4 16; do b rays_$n --backend compute --ao-rays $n; done
for v in rt_ao_compacted rt_ao_persistent; do b $v --backend compute --use-layer rt_ao=$v; done
for l in 0 0.05; do b driver_len_$l --backend rt-pipeline --ao-length $l; done
cd $OUT && tar czf results.tgz r
for d in r/*/; do n=$(basename $d)
  ao=$(grep -E "^atrium,[a-z-]+,ao/ao," $d/rays_passes.csv | cut -d, -f4)
  row=$(grep -E "^\| atrium " $d/rays.md | cut -d'|' -f5,7,8,9,14)
  st=$(grep -E "^\| Stress " $d/rays.md | cut -d'|' -f5,8 | tr '\n' ' ')
  echo "$n | AO ms $ao | $row | Stress $st"
done
rm -rf r
