#!/bin/bash
# Makes .gpu/diag.tgz for run.sh: one folder per variant with main's `shaders/`, `layers/` and
# `graph/` (the files of 1f35499), its trace/compute.wgsl patched by variants/VARIANT.patch.
set -eu
cd "$(dirname "$0")/../../.."
rm -rf /tmp/diag_trees && mkdir -p /tmp/diag_trees .gpu
for v in main alu alu1 loads; do
  mkdir -p /tmp/diag_trees/$v && git archive 1f35499 shaders layers graph | tar x -C /tmp/diag_trees/$v
  [ $v = main ] || patch -s -p1 -d /tmp/diag_trees/$v < docs/experiments/step_cost/variants/$v.patch
done
tar czf .gpu/diag.tgz -C /tmp/diag_trees main alu alu1 loads
