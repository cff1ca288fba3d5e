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
#     from an empty folder of its own (its built-in graph, layer and shader files): `bench build
#     --scenes organic,atrium --max-factor 1` twice each, and the after binary once with each
#     builder variant (the old bitonic sort, the old two dispatches a round, rounds over all
#     triangles, a local reduction to 128 and to 64 clusters); then Table 3 (`bench rays
#     --frames 10`) twice with the after binary and once with the before one.
#   part final2: the real assets with the coverage rows and a 1.93M-triangle file (`bench rays
#     --scenes HELMET,PINE,helmet_5x5x5 --coverage 0.02,0.05,0.1 --frames 10`): after binary on
#     both back-ends, then `compute` only with the AO schedules `rt_ao_compacted` and
#     `rt_ao_persistent` (`--use-layer`), and the before binary on `compute`.
#   part final3: `render --report` (2560x1440, 60 frames, `compute`) on the atrium copied 1 and
#     3 times per axis (262k and 7.1M unique triangles) with the five built-in graphs, before and
#     after (and after with RAYGRAPH_PASS_PER_NODE=1 for hybrid_denoised), and 5 times (32.8M)
#     for full RT and raster, after; then the pine with deferred alpha tests
#     (RAYGRAPH_DEFERRED_ALPHA=2, 4, 8) on `compute`.
#   part final4: after the fix of the AO schedules' counters (cleared before a run of compute
#     nodes recorded as one pass): the real assets with the coverage rows on `compute` with the
#     three AO schedules (`rt_ao`, `rt_ao_compacted`, `rt_ao_persistent`).
#   part final5: after the deferred alpha tests were taken out again (the pine 4% slower on
#     `compute` with them compiled in, off): before and after binaries, `compute` only, the box,
#     the helmet and the pine (`bench rays --scenes box,HELMET,PINE --frames 10`).
#   part executors: six box rows in one process (`--scenes box,box,box,box,box,box`), each on an
#     executor of its own, per back-end, two processes each, the SM clock sampled every 50 ms:
#     whether the slow executor of the probe strikes at random within a process.
set -u
PART=${1:-probe}
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
for b in raygraph raygraph-base; do [ -f .gpu/$b.gz ] && gunzip -f .gpu/$b.gz && chmod +x .gpu/$b; done
RG=$PWD/.gpu/raygraph; OLD=$PWD/.gpu/raygraph-base; ROOT=$PWD
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
elif [ "$PART" = final1 ]; then
  mkdir -p /tmp/run_old /tmp/run_new $OUT/r/build
  (cd /tmp/run_new && $RG bench rays --scenes box --backend compute --frames 5 --out /tmp/warm > /dev/null 2>&1)
  build() { local name=$1 bin=$2; shift 2
    (cd /tmp/run_new && env "$@" timeout 120 $bin bench build --scenes organic,atrium --max-factor 1 --out $OUT/r/build/$name > $OUT/r/build/$name.log 2>&1) || tail -3 $OUT/r/build/$name.log; }
  build base_1 $OLD X=1; build new_1 $RG X=1
  build new_bitonic $RG RAYGRAPH_GPU_BUILD_SORT=bitonic; build new_pair $RG RAYGRAPH_GPU_BUILD_ROUND=pair
  build new_direct $RG RAYGRAPH_GPU_BUILD_INDIRECT=0; build new_local128 $RG RAYGRAPH_GPU_BUILD_LOCAL=128
  build new_local64 $RG RAYGRAPH_GPU_BUILD_LOCAL=64; build base_2 $OLD X=1; build new_2 $RG X=1
  for k in new_1 base_1 new_2; do
    R=$RG; D=/tmp/run_new; case $k in base*) R=$OLD; D=/tmp/run_old;; esac
    T=170; [ $k = base_1 ] && T=120
    (cd $D && timeout $T $R bench rays --frames 10 --out $OUT/r/t3_$k > $OUT/r/t3_$k.log 2>&1) || tail -2 $OUT/r/t3_$k.log
  done
elif [ "$PART" = final2 ]; then
  mkdir -p /tmp/run_old /tmp/run_new
  REAL=$ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb,$ROOT/assets/gltf/smallpine/scene.gltf,/tmp/helmet_5x5x5.glb
  (cd /tmp/run_new && $RG scene export $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb /tmp/helmet_5x5x5.glb --duplicate 5 --no-dedup > /dev/null)
  real() { local name=$1 bin=$2 dir=$3; shift 3
    (cd $dir && timeout 200 $bin bench rays --scenes $REAL --coverage 0.02,0.05,0.1 --frames 10 "$@" --out $OUT/r/real_$name > $OUT/r/real_$name.log 2>&1) || tail -2 $OUT/r/real_$name.log; }
  real new $RG /tmp/run_new
  real new_compacted $RG /tmp/run_new --backend compute --use-layer rt_ao=rt_ao_compacted
  real new_persistent $RG /tmp/run_new --backend compute --use-layer rt_ao=rt_ao_persistent
  real base $OLD /tmp/run_old --backend compute
elif [ "$PART" = final3 ]; then
  mkdir -p /tmp/run_old /tmp/run_new $OUT/r/static
  rep() { local name=$1 bin=$2 dir=$3 graph=$4; shift 4
    echo "== $name graph/$graph.ron $*" >> $OUT/r/static.txt
    (cd $dir && timeout 100 $bin render --graph graph/$graph.ron "$@" --backend compute --width 2560 --height 1440 --frames 60 --report $OUT/r/static/$name --out /tmp/o.png 2>&1 | grep -E "^total|frame wall|outside the passes|rror" >> $OUT/r/static.txt); }
  for dup in 1 3; do for g in raster hybrid hybrid_denoised full_rt ao; do
    copies=""; [ $dup = 1 ] || copies="--duplicate $dup --no-dedup"
    rep new_${g}_$dup $RG /tmp/run_new $g --scene atrium $copies
    rep base_${g}_$dup $OLD /tmp/run_old $g --scene atrium $copies
  done; done
  RAYGRAPH_PASS_PER_NODE=1 rep new_pernode_hybrid_denoised_1 $RG /tmp/run_new hybrid_denoised --scene atrium
  for g in full_rt raster; do rep new_${g}_5 $RG /tmp/run_new $g --scene atrium --duplicate 5 --no-dedup; done
  for n in 0 2 4 8; do
    (cd /tmp/run_new && RAYGRAPH_DEFERRED_ALPHA=$n timeout 100 $RG bench rays --scenes $ROOT/assets/gltf/smallpine/scene.gltf --coverage 0.02,0.05 --backend compute --frames 10 --out $OUT/r/pine_defer$n > $OUT/r/pine_defer$n.log 2>&1) || tail -2 $OUT/r/pine_defer$n.log
  done
elif [ "$PART" = final4 ]; then
  mkdir -p /tmp/run_new
  REAL=$ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb,$ROOT/assets/gltf/smallpine/scene.gltf,/tmp/helmet_5x5x5.glb
  (cd /tmp/run_new && $RG scene export $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb /tmp/helmet_5x5x5.glb --duplicate 5 --no-dedup > /dev/null)
  for v in rt_ao rt_ao_compacted rt_ao_persistent; do
    (cd /tmp/run_new && timeout 150 $RG bench rays --scenes $REAL --coverage 0.02,0.05,0.1 --frames 10 --backend compute --use-layer rt_ao=$v --out $OUT/r/real_$v > $OUT/r/real_$v.log 2>&1) || tail -2 $OUT/r/real_$v.log
  done
elif [ "$PART" = final5 ]; then
  mkdir -p /tmp/run_old /tmp/run_new
  S=box,$ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb,$ROOT/assets/gltf/smallpine/scene.gltf
  for k in new base; do
    R=$RG; D=/tmp/run_new; [ $k = base ] && R=$OLD && D=/tmp/run_old
    (cd $D && timeout 100 $R bench rays --scenes $S --backend compute --frames 10 --out $OUT/r/t_$k > $OUT/r/t_$k.log 2>&1) || tail -2 $OUT/r/t_$k.log
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
for f in r/build_*/gpu_build.md; do [ -f $f ] && echo "== $f" && grep -E "^\| (organic|atrium)" $f; done
[ -f box.log ] && cat box.log; [ -f report.txt ] && grep -E "^==|^total|frame wall|outside the passes" report.txt | head -60
for f in r/build/*/gpu_build.md; do [ -f $f ] && echo "== $f" && grep -E "^\| (organic|atrium)" $f | cut -d'|' -f2-12; done
for f in r/t3_* r/real_* r/pine_* r/t_*; do [ -f $f/rays.md ] && echo "== $f" && grep -E "^\| " $f/rays.md | grep -v -- "---" | cut -d'|' -f2-3,5,7,8,15; done
[ -f r/static.txt ] && grep -E "^==|outside" r/static.txt
rm -rf r
