#!/bin/bash
# Makes .gpu/diag.tgz for run.sh: one folder per variant with `shaders/`, `layers/` and `graph/`
# of the commit given (default HEAD), patched by variants/VARIANT.patch (main: unpatched).
set -eu
cd "$(dirname "$0")/../../.."
rev=${1:-HEAD}
variants="alpha_off alpha_twice shadow_notrace"
rm -rf /tmp/diag_trees && mkdir -p /tmp/diag_trees .gpu
for v in main $variants; do
  mkdir -p /tmp/diag_trees/$v && git archive $rev shaders layers graph | tar x -C /tmp/diag_trees/$v
  [ $v = main ] || patch -s -p1 -d /tmp/diag_trees/$v < docs/experiments/low_coverage/variants/$v.patch
done
tar czf .gpu/diag.tgz -C /tmp/diag_trees main $variants
