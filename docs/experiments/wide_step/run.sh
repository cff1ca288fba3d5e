#!/bin/bash
# PERF.md step 59 (diagnostic, compute): what a wide node's step would cost, emulated on the
# binary layout: each interior step of the BLAS traversal also loads and tests the boxes of the
# 2 (`step4`) or 6 (`step8`) nodes stored after the two children, in the same round as theirs
# (128 or 256 contiguous bytes, as a 4- or 8-wide node's boxes), their result kept by a
# comparison that never holds; the same rays, steps and images. Main, `step4`, `step8`, main on
# the helmet and the pine at their cameras and at 2% and 10%; then main, `step4`, `step8` on
# Table 3. Made by `bash docs/experiments/low_coverage/pack.sh a4c1ea1
# docs/experiments/wide_step step4 step8`. Results in $OUT/wide_step.tgz.
. docs/experiments/low_coverage/preamble.sh
REAL=$REAL_ENDS
for v in main step4 step8 main; do bench $v real; done
for v in main step4 step8; do bench $v table3; done
cd $OUT && tar czf wide_step.tgz r && rm -rf r
