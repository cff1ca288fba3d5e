# Sourced by the device scripts under docs/experiments on the GPU machine: unpacks the GL
# packages, the release binary and the variant folders (.gpu/diag.tgz into /tmp/v), prints the
# device, and sets ROOT, RG (the binary), OUT (results, with $OUT/r made) and REAL (the helmet and
# the pine at their cameras and at 2%, 5%, 10% of the frame; REAL_ALL and REAL_ENDS below);
# defines `bench`, `kstats`, `export_copies`, `selftest`, `bench_both` and `shipped` (below).
set -u
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
xz -dc .gpu/raygraph.xz > .gpu/raygraph; chmod +x .gpu/raygraph
ROOT=$PWD; RG=$ROOT/.gpu/raygraph; OUT=${OUT:-/tmp/out}; mkdir -p $OUT/r /tmp/v
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
tar xzf .gpu/diag.tgz -C /tmp/v
REAL_SCENES="$ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb,$ROOT/assets/gltf/smallpine/scene.gltf"
REAL="--scenes $REAL_SCENES --coverage 0.02,0.05,0.1"

# bench NAME WHAT: `bench rays --backend compute --frames 10` in variant folder NAME, Table 3
# (WHAT=table3) or the real assets (WHAT=real), into $OUT/r/NAME_WHAT (NAME_WHAT_2 the second
# time); skipped past $DEADLINE seconds (default 530); prints each row's GPU and wall ms.
bench() {
  local name=$1 what=$2 n=${1}_$2 args=""
  [ -d $OUT/r/$n ] && n=${n}_2
  [ $what = real ] && args="$REAL"
  if [ $SECONDS -gt ${DEADLINE:-530} ]; then echo "deadline: $n skipped"; return; fi
  (cd /tmp/v/$name && timeout 150 $RG bench rays $args --backend compute --frames 10 --out $OUT/r/$n > $OUT/r/$n.log 2>&1) || tail -2 $OUT/r/$n.log
  echo "== $n ($SECONDS s)"; grep -E "^\| " $OUT/r/$n/rays.md | grep -v -- "---" | grep -v " test |" | awk -F'|' '{print $2 "|" $5 "|" $6}' | sed 's|/[^ ]*/||'
}
# kstats NAME WHAT RENDER_ARGS...: one 320x180 frame of the compute back-end in variant folder
# NAME with `--kernel-stats` into $OUT/r/NAME_WHAT.md; prints each kernel's registers, binary
# size and local memory (its low 32 bits: the driver reports 2^36 plus the bytes).
kstats() {
  local name=$1 what=$2; shift 2
  (cd /tmp/v/$name && timeout 120 $RG render "$@" --backend compute --width 320 --height 180 --frames 1 \
    --out $OUT/r/${name}_$what.png --kernel-stats $OUT/r/${name}_$what.md > $OUT/r/${name}_$what.log 2>&1) || tail -3 $OUT/r/${name}_$what.log
  echo "== $name $what"; awk '/^## /{k=$2} /Register Count/ {r=$5} /Binary Size/ {b=$5} /Local Memory/ {print "  " k " registers " r ", binary " b ", local bytes " $6 % 4294967296}' $OUT/r/${name}_$what.md
}
# REAL_ALL: REAL with helmet_5x5x5 (the helmet 125 times, 1.93M triangles, which
# `export_copies` writes to /tmp).
REAL_ALL="--scenes $REAL_SCENES,/tmp/helmet_5x5x5.glb --coverage 0.02,0.05,0.1"
# REAL_ENDS: the helmet and the pine at their cameras and at 2% and 10% of the frame only.
REAL_ENDS="--scenes $REAL_SCENES --coverage 0.02,0.1"
export_copies() {
  $RG scene export $ROOT/assets/gltf/DamagedHelmet/DamagedHelmet.glb /tmp/helmet_5x5x5.glb --duplicate 5 --no-dedup > /dev/null
}
# selftest: `raygraph selftest` into $OUT/r/selftest.log; prints its exit and its summary.
selftest() {
  timeout 150 $RG selftest > $OUT/r/selftest.log 2>&1; echo "selftest exit $?"
  grep -E "passed|failed|not applicable" $OUT/r/selftest.log | tail -3
}
# bench_both WHAT: `bench rays --frames 10` on both back-ends of this checkout, Table 3
# (WHAT=table3, into $OUT/r/table3) or the real assets with helmet_5x5x5 (WHAT=real, $OUT/r/real);
# prints each row.
bench_both() {
  local what=$1 args=""
  [ $what = real ] && args="$REAL_ALL"
  timeout 240 $RG bench rays $args --frames 10 --out $OUT/r/$what > $OUT/r/$what.log 2>&1 || tail -2 $OUT/r/$what.log
  echo "== $what ($SECONDS s)"; grep -E "^\| " $OUT/r/$what/rays.md | grep -v -- "---" | grep -v " test |" | awk -F'|' '{print $2 "|" $3 "|" $5 "|" $6}' | sed 's|/[^ ]*/||'
}
# shipped: this checkout as it is: selftest, then both back-ends on Table 3 and the real assets
# (the helmet, the pine and helmet_5x5x5 at their cameras and at 2%, 5%, 10% of the frame).
shipped() {
  selftest
  export_copies
  bench_both table3
  bench_both real
}
