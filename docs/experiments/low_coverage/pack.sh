#!/bin/bash
# Makes .gpu/diag.tgz for run.sh: one folder per variant with `shaders/`, `layers/` and `graph/`
# of commit REV (default HEAD), patched by DIR/variants/VARIANT.patch (main: unpatched).
# `pack.sh [REV [DIR [VARIANT...]]]`; without DIR, this experiment's variants; with DIR alone, main only.
set -eu
cd "$(dirname "$0")/../../.."
rev=${1:-HEAD}
if [ $# -ge 2 ]; then
  dir=$2; shift 2; variants=$*
else
  dir=docs/experiments/low_coverage; variants="alpha_off alpha_twice shadow_notrace"
fi
rm -rf /tmp/diag_trees && mkdir -p /tmp/diag_trees .gpu
for v in main $variants; do
  mkdir -p /tmp/diag_trees/$v && git archive $rev shaders layers graph | tar x -C /tmp/diag_trees/$v
  [ $v = main ] || patch -s -p1 -d /tmp/diag_trees/$v < $dir/variants/$v.patch
done
tar czf .gpu/diag.tgz -C /tmp/diag_trees main $variants
