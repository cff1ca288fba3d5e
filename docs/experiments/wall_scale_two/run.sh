#!/bin/bash
# The GPU-machine runs of the second round on the wall-time-and-scale issue. One device call
# per part; results under $OUT (one tgz and a log), the short tables printed last.
#   part probe: before any change (binary .gpu/raygraph of main):
#     1. the driver's box row, whose first run of a session was 4-5x slow (BENCHMARKS.md,
#        "The restructuring of the house, step two"): `bench rays --scenes box --backend
#        rt-pipeline` four times, each with the NVIDIA driver's shader disk cache in a folder of
#        its own: cold (empty folder), warm (same folder again), cold (another), then with the
#        disk cache off; the SM clock sampled every 100 ms throughout (clocks.csv).
#     2. `bench build --scenes organic,atrium --max-factor 1` with the builder's tuning knobs
#        (RAYGRAPH_GPU_BUILD_LOCAL 256 = default, 128, 64; RAYGRAPH_GPU_BUILD_FINISH 512).
#     3. `render --report` of hybrid_denoised, hybrid, raster and full RT on the atrium at
#        2560x1440 (the CPU phases outside the passes, and every pass's CPU ms).
#   part final1: binaries .gpu/raygraph-base (42c239d, before) and .gpu/raygraph (after), each
#     from an empty folder of its own (its built-in graph, layer and shader files): Table 3
#     (`bench rays --frames 10`) twice with the new binary and once with the old; `bench build
#     --scenes organic,atrium --max-factor 1` twice each.
#   part final2: the real assets with the coverage rows and a 1.93M-triangle file (`bench rays
#     --scenes HELMET,PINE,helmet_5x5x5 --coverage 0.02,0.05,0.1`), old binary, new binary and
#     the new binary's AO variant ($AO_VARIANT_ENV); then `render --report` on the atrium
#     copied 1 and 3 times per axis (262k and 7.1M unique triangles) for the five built-in
#     graphs, old and new, and 5 times (32.8M) for full RT and raster, new.
#   part executors: six box rows in one process (`--scenes box,box,box,box,box,box`), each on an
#     executor of its own, per back-end, two processes each, the SM clock sampled every 50 ms:
#     whether the slow executor of the probe strikes at random within a process.
set -u
PART=${1:-probe}
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
[ -f .gpu/raygraph.gz ] && gunzip -f .gpu/raygraph.gz && chmod +x .gpu/raygraph
RG=$PWD/.gpu/raygraph; ROOT=$PWD
OUT=${OUT:-/tmp/out}; mkdir -p $OUT/r
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv,noheader
nvidia-smi --query-gpu=timestamp,clocks.sm,utilization.gpu --format=csv,noheader -lms 100 > $OUT/r/clocks.csv 2>&1 &
SMI=$!
if [ "$PART" = probe ]; then
  mkdir -p /tmp/empty && cd /tmp/empty
  for k in cold1:/tmp/cache1 warm1:/tmp/cache1 cold2:/tmp/cache2 off:; do
    name=${k%%:*}; dir=${k#*:}
    echo "== box rt-pipeline, shader cache $name, $(date -u +%T.%N)" | tee -a $OUT/r/box.log
    if [ -n "$dir" ]; then mkdir -p $dir; export __GL_SHADER_DISK_CACHE=1 __GL_SHADER_DISK_CACHE_PATH=$dir; else export __GL_SHADER_DISK_CACHE=0; fi
    $RG bench rays --scenes box --backend rt-pipeline --frames 10 --out $OUT/r/box_$name > $OUT/r/box_$name.log 2>&1
    grep -E "^\| box" $OUT/r/box_$name/rays.md | cut -d'|' -f2-7 | tee -a $OUT/r/box.log
  done
  unset __GL_SHADER_DISK_CACHE __GL_SHADER_DISK_CACHE_PATH
  for k in default:256:1024 local128:128:1024 local64:64:1024 finish512:256:512; do
    name=${k%%:*}; rest=${k#*:}
    RAYGRAPH_GPU_BUILD_LOCAL=${rest%%:*} RAYGRAPH_GPU_BUILD_FINISH=${rest#*:} $RG bench build --scenes organic,atrium --max-factor 1 --backend compute --out $OUT/r/build_$name > $OUT/r/build_$name.log 2>&1
  done
  cd $ROOT
  for g in hybrid_denoised hybrid raster full_rt; do
    echo "== render --report, atrium, graph/$g.ron" >> $OUT/r/report.txt
    $RG render --scene atrium --graph graph/$g.ron --backend compute --width 2560 --height 1440 --frames 60 --report $OUT/r/report_$g.md --out /tmp/o.png >> $OUT/r/report.txt 2>&1
  done
elif [ "$PART" = executors ]; then
  kill $SMI; mkdir -p /tmp/e && cd /tmp/e
  nvidia-smi --query-gpu=timestamp,clocks.sm,clocks.mem,utilization.gpu,clocks_throttle_reasons.active --format=csv,noheader -lms 50 > $OUT/clocks.csv & SMI=$!
  for k in 1 2; do for b in rt-pipeline compute; do
    date -u +%T.%N; $RG bench rays --scenes box,box,box,box,box,box --backend $b --frames 10 --out /tmp/e/r_${b}_$k > /dev/null 2>&1
  done; done
  kill $SMI
  for k in 1 2; do for b in rt-pipeline compute; do
    echo "== $b $k"; grep -E "^box," /tmp/e/r_${b}_$k/rays_passes.csv | grep -E "ao/ao|tonemap" | tr '\n' ' '; echo
  done; done
  tar czf $OUT/e.tgz r_*; exit 0
fi
kill $SMI
cd $OUT && tar czf results.tgz r && cp r/box.log r/report.txt . 2>/dev/null
for f in r/build_*/gpu_build.md; do echo "== $f"; grep -E "^\| (organic|atrium)" $f; done
cat box.log; grep -E "^==|^total|frame wall|outside the passes" report.txt | head -60
rm -rf r
