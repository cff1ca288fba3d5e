#!/bin/bash
# PERF.md step 62 (diagnostic, compute): `step4` (step 59) and `step4_pushed` (the same, and the
# children put in an order fixed by the ray's octant, the last two written to the free stack
# slots above the stack pointer, as a 4-wide visit in an order chosen at build time would push
# them); the same rays, steps and images. Main, `step4`, `step4_pushed`, main on the helmet and
# the pine at their cameras and at 2% and 10%; then main, `step4`, `step4_pushed` on Table 3.
# Made by `bash docs/experiments/low_coverage/pack.sh 44df518 docs/experiments/wide_step step4
# step4_pushed`. Results in $OUT/wide_step_pushed.tgz.
. docs/experiments/low_coverage/preamble.sh
REAL=$REAL_ENDS
for v in main step4 step4_pushed main; do bench $v real; done
for v in main step4 step4_pushed; do bench $v table3; done
cd $OUT && tar czf wide_step_pushed.tgz r && rm -rf r
