#!/bin/bash
# PERF.md step 57 (diagnostic, compute): whether the traced passes of a low-coverage frame wait
# on a tree that is not in the L2 cache. `warm`: every invocation of the primary, shadow and
# spread-AO passes first loads one 32-byte sector of the BLAS nodes and of the triangles (its
# linear index's; none past their ends), so that a pass's first invocations, sky pixels at the
# top of the image, bring the tree into L2 before the covered pixels' rays need it. Main,
# `warm`, main, `warm` on the helmet and the pine at their cameras and at 2% and 10%; then main
# and `warm` on Table 3. Made by `bash docs/experiments/low_coverage/pack.sh 90a4bd2
# docs/experiments/l2_warm warm`. Results in $OUT/l2_warm.tgz.
. docs/experiments/low_coverage/preamble.sh
REAL=$REAL_ENDS
for v in main warm main warm; do bench $v real; done
for v in main warm; do bench $v table3; done
cd $OUT && tar czf l2_warm.tgz r && rm -rf r
