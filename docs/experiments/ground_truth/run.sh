#!/bin/bash
# The GPU-machine runs of the ground-truth issue: every mode against the path-traced reference
# (`bench truth`), and raygraph's path-traced references for the Mitsuba comparison
# (tools/mitsuba/compare.py runs on the CPU machine, against these EXRs). Binary .gpu/raygraph
# (release, of the commit the results name), run from an empty folder (its built-in files).
#   part truth1: `bench truth` at 1280x720 on `compute`, 16 paths a pixel and frame, 256 frames
#     (and the warm-up's) for the reference, 64 timed frames per mode: the atrium from its
#     camera; the helmet from its camera and covering 2%, 5% and 10% of the frame.
#   part truth2: the same for the pine (its camera, 2%, 5%, 10%) and the 1.93M-triangle file
#     (the helmet copied 5x5x5 without de-duplication: its camera, 5%, 10%).
#   part truth3: the same file at 2% (its camera again), with the warm-up's full-load kernel
#     (before it, that view's timings did not repeat: BENCHMARKS.md "The row that did not repeat").
#   part refs: `render --graph reference (16 paths a frame) --frames 256` (4,096 paths a pixel
#     and the warm-up's) to linear EXR at 256x256 for cornell, box, default and Khronos'
#     NormalTangentMirrorTest, and at 256x144 for the atrium and the helmet: the images
#     compare.py checks against Mitsuba 3 (docs/experiments/ground_truth/mitsuba.sh renders them
#     on the local device instead).
set -u
PART=${1:-truth1}
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
[ -f .gpu/raygraph.gz ] && gunzip -f .gpu/raygraph.gz && chmod +x .gpu/raygraph
RG=$PWD/.gpu/raygraph; ROOT=$PWD
OUT=${OUT:-/tmp/out}; mkdir -p $OUT/r
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv,noheader | tee $OUT/r/device.txt
HELMET=$ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb
PINE=$ROOT/assets/gltf/smallpine/scene.gltf
mkdir -p /tmp/empty && cd /tmp/empty
TRUTH="bench truth --backend compute --width 1280 --height 720 --reference-samples 16 --reference-frames 256 --mode-frames 64"
case $PART in
  truth1)
    timeout 270 $RG $TRUTH --scenes atrium --out $OUT/r/atrium > $OUT/r/atrium.log 2>&1
    timeout 280 $RG $TRUTH --scenes helmet=$HELMET --coverage 0.02,0.05,0.1 --out $OUT/r/helmet > $OUT/r/helmet.log 2>&1
    ;;
  truth2)
    $RG scene export $HELMET /tmp/helmet_5x5x5.glb --duplicate 5 --no-dedup > /dev/null
    timeout 280 $RG $TRUTH --scenes pine=$PINE --coverage 0.02,0.05,0.1 --out $OUT/r/pine > $OUT/r/pine.log 2>&1
    timeout 280 $RG $TRUTH --scenes helmet_5x5x5=/tmp/helmet_5x5x5.glb --coverage 0.05,0.1 --out $OUT/r/helmet_5x5x5 > $OUT/r/helmet_5x5x5.log 2>&1
    ;;
  truth3)
    $RG scene export $HELMET /tmp/helmet_5x5x5.glb --duplicate 5 --no-dedup > /dev/null
    timeout 400 $RG $TRUTH --scenes helmet_5x5x5=/tmp/helmet_5x5x5.glb --coverage 0.02 --out $OUT/r/helmet_5x5x5_2 > $OUT/r/helmet_5x5x5_2.log 2>&1
    ;;
  refs)
    mkdir -p $OUT/r/refs
    sed 's/"path": Layer(layer: "rt_path", inputs/"path": Layer(layer: "rt_path", params: {"samples": 16}, inputs/' $ROOT/graph/reference.ron > /tmp/empty/reference16.ron
    NTMT=$ROOT/assets/khronos/NormalTangentMirrorTest/glTF/NormalTangentMirrorTest.gltf
    for s in cornell:256:256 box:256:256 default:256:256 atrium:256:144 helmet=$HELMET:256:144 ntmt=$NTMT:256:256; do
      spec=${s%%:*}; rest=${s#*:}; name=${spec%%=*}; scene=${spec#*=}
      $RG render --graph /tmp/empty/reference16.ron --backend compute --scene $scene --width ${rest%%:*} --height ${rest#*:} --frames 256 --out $OUT/r/refs/$name.exr > $OUT/r/refs/ref_$name.log 2>&1
      grep -E "path/path|wall" $OUT/r/refs/ref_$name.log
    done
    ;;
esac
# One archive per folder (at most 16 MiB a file comes back): the tables, logs, and the images of
# each scene's own view (the coverage views' and the equal-time path tracer's images stay).
cd $OUT/r
for d in */; do
  d=${d%/}
  tar czf $OUT/${PART}_$d.tgz --exclude='*_at_*.png' --exclude='*path_tracer*.png' $d
  grep -hE "^\| " $d/*.md | head -60
done
tar czf $OUT/${PART}_logs.tgz --exclude='*/' *.* 2>/dev/null
cd $OUT && rm -rf r
