#!/usr/bin/env bash
# raygraph's path tracer against Mitsuba 3, run on the CPU machine. For each scene, raygraph's
# linear EXR (rendered here on the local Vulkan device, 16 paths a pixel and frame over FRAMES
# frames and the warm-up's; or taken from EXR_DIR/NAME.exr, e.g. the GPU machine's
# `run.sh refs`), then tools/mitsuba/compare.py: Mitsuba's reference (llvm_ad_rgb, SPP samples,
# unlimited path length), relMSE, HDR-FLIP and both mean radiances. Needs the venv of
# tools/mitsuba/README.md (MI_VENV) and DRJIT_LIBLLVM_PATH.
#   bash docs/experiments/ground_truth/mitsuba.sh OUT [name=scene:width:height ...]
set -eu
OUT=${1:?usage: mitsuba.sh OUT [name=scene:width:height ...]}; shift
ROOT=$(cd "$(dirname "$0")/../../.." && pwd)
RG=${RAYGRAPH:-$ROOT/target/release/raygraph}
FRAMES=${FRAMES:-256}
SPP=${SPP:-4096}
MI_VENV=${MI_VENV:-$HOME/mi-venv}
HELMET=$ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb
NTMT=$ROOT/assets/khronos/NormalTangentMirrorTest/glTF/NormalTangentMirrorTest.gltf
SCENES=${*:-cornell:256:256 box:256:256 default:256:256 atrium:256:144 helmet=$HELMET:256:144 ntmt=$NTMT:256:256}
mkdir -p "$OUT"
sed 's/"path": Layer(layer: "rt_path", inputs/"path": Layer(layer: "rt_path", params: {"samples": 16}, inputs/' \
  "$ROOT/graph/reference.ron" > "$OUT/reference16.ron"
for s in $SCENES; do
  spec=${s%%:*}; size=${s#*:}; name=${spec%%=*}; scene=${spec#*=}; width=${size%%:*}; height=${size#*:}
  exr=$OUT/$name.exr
  if [ -n "${EXR_DIR:-}" ]; then
    exr=$EXR_DIR/$name.exr
  else
    "$RG" render --graph "$OUT/reference16.ron" --backend compute --scene "$scene" --width "$width" \
      --height "$height" --frames "$FRAMES" --out "$exr" > "$OUT/raygraph_$name.log" 2>&1
  fi
  "$MI_VENV/bin/python" "$ROOT/tools/mitsuba/compare.py" "$scene" --width "$width" --height "$height" \
    --spp "$SPP" --test "$exr" --raygraph "$RG" --out "$OUT/$name" 2>&1 | grep -v '^\[' | tee "$OUT/$name.log"
done
