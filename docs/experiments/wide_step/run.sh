#!/bin/bash
# PERF.md steps 59, 61 and 62 (diagnostic, compute): what a wide node's step would cost,
# emulated on the binary layout. `run.sh NAME VARIANT...`: main, each variant, main on the
# helmet and the pine at their cameras and at 2% and 10%; then main and each variant on
# Table 3; results in $OUT/NAME.tgz. The variants (docs/experiments/wide_step/variants; the
# same rays, steps and images as main): `step4` and `step8`, each interior step of the BLAS
# traversal also loading and testing the boxes of the 2 or 6 nodes stored after the two children
# in the same round as theirs (128 or 256 contiguous bytes, as a 4- or 8-wide node's boxes),
# their result kept by a comparison that never holds; `step4_sorted`, `step4` and the four
# entries ordered by a network of five compare-swaps, the two farthest written to the free stack
# slots above the stack pointer; `step4_pushed`, `step4` and the children put in an order fixed
# by the ray's octant, the last two written likewise.
#   step 59: `bash docs/experiments/low_coverage/pack.sh a4c1ea1 docs/experiments/wide_step step4
#            step8 && bash docs/experiments/wide_step/run.sh wide_step step4 step8`
#   step 61: `... pack.sh e612df7 docs/experiments/wide_step step4 step4_sorted && bash
#            docs/experiments/wide_step/run.sh wide_step_sorted step4 step4_sorted`
#   step 62: `... pack.sh 44df518 docs/experiments/wide_step step4 step4_pushed && bash
#            docs/experiments/wide_step/run.sh wide_step_pushed step4 step4_pushed`
. docs/experiments/low_coverage/preamble.sh
name=$1; shift
REAL=$REAL_ENDS
for v in main "$@" main; do bench $v real; done
for v in main "$@"; do bench $v table3; done
cd $OUT && tar czf $name.tgz r && rm -rf r
