#!/bin/bash
# The clock pump (src/runtime/clock_pump.rs: 0.3 s of a full-load kernel before every warm-up on
# a hardware GPU) on the GPU machine. Binaries .gpu/raygraph-base (before) and .gpu/raygraph
# (after), each run from an empty folder of its own; the GPU's SM clock, utilisation and
# throttle reasons sampled every 100 ms throughout (clocks.csv).
#   part rows: the row that did not repeat (the 1.93M-triangle file, the helmet copied 5x5x5
#     without de-duplication, covering 2% of the frame: `bench rays --scenes FILE --coverage
#     0.02`), before, after, before, after; then `bench build --scenes organic,atrium
#     --max-factor 1` twice with the after binary.
#   part tables: Table 3 (`bench rays --frames 10`) twice, and the real assets with their
#     coverage rows (`bench rays --scenes HELMET,PINE --coverage 0.02,0.05,0.1 --frames 10`)
#     twice, with the after binary.
set -u
PART=${1:-rows}
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
for b in raygraph raygraph-base; do [ -f .gpu/$b.gz ] && gunzip -f .gpu/$b.gz && chmod +x .gpu/$b; done
RG=$PWD/.gpu/raygraph; OLD=$PWD/.gpu/raygraph-base; ROOT=$PWD
HELMET=$ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb
PINE=$ROOT/assets/gltf/smallpine/scene.gltf
OUT=${OUT:-/tmp/out}; mkdir -p $OUT/r/$PART
R=$OUT/r/$PART
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv,noheader | tee $R/device.txt
nvidia-smi --query-gpu=timestamp,clocks.sm,utilization.gpu,clocks_throttle_reasons.active --format=csv,noheader -lms 100 > $R/clocks.csv 2>&1 &
SMI=$!
mkdir -p /tmp/run_old /tmp/run_new
mark() { echo "$1 $(date -u +%T.%N)" >> $R/marks.txt; }
if [ "$PART" = rows ]; then
  $RG scene export $HELMET /tmp/helmet_5x5x5.glb --duplicate 5 --no-dedup > $R/export.log 2>&1 || { cat $R/export.log; exit 1; }
  for k in base_1 new_1 base_2 new_2; do
    bin=$RG; dir=/tmp/run_new; case $k in base*) bin=$OLD; dir=/tmp/run_old;; esac
    mark "$k start"
    (cd $dir && timeout 120 $bin bench rays --scenes /tmp/helmet_5x5x5.glb --coverage 0.02 --frames 10 --out $R/unstable_$k > $R/unstable_$k.log 2>&1) || tail -2 $R/unstable_$k.log
    mark "$k end"
    grep -E "at 2%" $R/unstable_$k/rays.md | cut -d'|' -f2-6,15
  done
  for k in 1 2; do
    mark "build_$k start"
    (cd /tmp/run_new && timeout 100 $RG bench build --scenes organic,atrium --max-factor 1 --out $R/build_$k > $R/build_$k.log 2>&1) || tail -2 $R/build_$k.log
    mark "build_$k end"
  done
else
  for k in 1 2; do
    mark "t3_$k start"
    (cd /tmp/run_new && timeout 150 $RG bench rays --frames 10 --out $R/t3_$k > $R/t3_$k.log 2>&1) || tail -2 $R/t3_$k.log
    mark "real_$k start"
    (cd /tmp/run_new && timeout 110 $RG bench rays --scenes $HELMET,$PINE --coverage 0.02,0.05,0.1 --frames 10 --out $R/real_$k > $R/real_$k.log 2>&1) || tail -2 $R/real_$k.log
    mark "real_$k end"
  done
fi
kill $SMI
cd $OUT/r && tar czf $OUT/$PART.tgz $PART && rm -rf $PART
