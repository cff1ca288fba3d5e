#!/bin/bash
# Makes .gpu/diag.tgz for run.sh: one folder per variant with main's `shaders/`, `layers/` and
# `graph/` (the files of 1f35499), its trace/compute.wgsl patched by variants/VARIANT.patch.
# `pack.sh DIR V1 V2 ...` does the same for the patches of another experiment's folder (step_ops).
set -eu
cd "$(dirname "$0")/../../.."
dir=${1:-docs/experiments/step_cost}; shift || true
variants=${*:-alu alu1 loads}
rm -rf /tmp/diag_trees && mkdir -p /tmp/diag_trees .gpu
for v in main $variants; do
  mkdir -p /tmp/diag_trees/$v && git archive 1f35499 shaders layers graph | tar x -C /tmp/diag_trees/$v
  [ $v = main ] || patch -s -p1 -d /tmp/diag_trees/$v < $dir/variants/$v.patch
done
tar czf .gpu/diag.tgz -C /tmp/diag_trees main $variants
