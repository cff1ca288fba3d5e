#!/bin/bash
# Makes .gpu/diag.tgz for run.sh: one folder per variant with `shaders/`, `layers/` and `graph/`
# of commit REV (default HEAD), patched by DIR/variants/VARIANT.patch (main: unpatched).
# `pack.sh [REV [DIR VARIANT...]]`; without DIR, this experiment's variants.
set -eu
cd "$(dirname "$0")/../../.."
rev=${1:-HEAD}
dir=${2:-docs/experiments/low_coverage}
shift 2 2>/dev/null || shift $#
variants=${*:-alpha_off alpha_twice shadow_notrace}
rm -rf /tmp/diag_trees && mkdir -p /tmp/diag_trees .gpu
for v in main $variants; do
  mkdir -p /tmp/diag_trees/$v && git archive $rev shaders layers graph | tar x -C /tmp/diag_trees/$v
  [ $v = main ] || patch -s -p1 -d /tmp/diag_trees/$v < $dir/variants/$v.patch
done
tar czf .gpu/diag.tgz -C /tmp/diag_trees main $variants
