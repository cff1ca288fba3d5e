# Sourced by low_coverage/run.sh and wide_any/run.sh on the GPU machine: unpacks the GL packages,
# the release binary and the variant folders (.gpu/diag.tgz into /tmp/v), prints the device, and
# sets ROOT, RG (the binary), OUT (results, with $OUT/r made) and REAL (the helmet and the pine at
# their cameras and at 2%, 5%, 10% of the frame).
set -u
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
xz -dc .gpu/raygraph.xz > .gpu/raygraph; chmod +x .gpu/raygraph
ROOT=$PWD; RG=$ROOT/.gpu/raygraph; OUT=${OUT:-/tmp/out}; mkdir -p $OUT/r /tmp/v
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
tar xzf .gpu/diag.tgz -C /tmp/v
REAL="--scenes $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb,$ROOT/assets/gltf/smallpine/scene.gltf --coverage 0.02,0.05,0.1"
