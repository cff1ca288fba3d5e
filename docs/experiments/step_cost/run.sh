#!/bin/bash
# PERF.md step 30: what an interior BLAS step's time is made of, by adding to it. Main's files
# (1f35499) run by the release binary of 6276040, whose trace shaders of main bind no pairs;
# variants of main's trace/compute.wgsl (.gpu/diag.tgz, made by pack.sh from the patches in variants/): `alu` (the integer
# work the 16-bit pairs of step 29 added, about 25 operations per child, on both children),
# `alu1` (the same on the left child only) and `loads` (two more 16-byte loads per step, of the
# node after the pair), each folded into a descriptor through a mask that is zero at run time.
# `bench rays --backend compute --frames 10`, Table 3, main first and last. Results in
# $OUT/step_cost.tgz.
set -u
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
xz -dc .gpu/raygraph.xz > .gpu/raygraph; chmod +x .gpu/raygraph
ROOT=$PWD; OUT=${OUT:-/tmp/out}; mkdir -p $OUT/r /tmp/v
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
tar xzf .gpu/diag.tgz -C /tmp/v
# `VARIANTS="a b" run.sh` runs main, those variants and main again (step_ops).
for name in main ${VARIANTS:-alu alu1 loads} main; do
  n=$name; [ -d $OUT/r/$n ] && n=${name}_2
  if [ $SECONDS -gt ${DEADLINE:-500} ]; then echo "deadline: $n skipped"; continue; fi
  (cd /tmp/v/$name && timeout 150 $ROOT/.gpu/raygraph bench rays --backend compute --frames 10 --out $OUT/r/$n > $OUT/r/$n.log 2>&1) || tail -2 $OUT/r/$n.log
  echo "== $n ($SECONDS s)"; grep -E "^\| " $OUT/r/$n/rays.md | grep -v -- "---" | grep -v " test |" | cut -d'|' -f2,3,5,6 | sed 's|/[^ ]*/||'
done
cd $OUT && tar czf step_cost.tgz r && rm -rf r
