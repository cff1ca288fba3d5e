#!/bin/bash
# PERF.md step 61 (diagnostic, compute): step 59's `step4` (a binary step that also loads and
# tests the boxes of the 2 nodes after the two children) and `step4_sorted` (the same, and the
# four entries ordered by a network of five compare-swaps, the two farthest written to the free
# stack slots above the stack pointer, as a sorted 4-wide visit does); the same rays, steps and
# images. Main, `step4`, `step4_sorted`, main on the helmet and the pine at their cameras and at
# 2% and 10%; then main, `step4`, `step4_sorted` on Table 3. Made by `bash
# docs/experiments/low_coverage/pack.sh e612df7 docs/experiments/wide_step step4 step4_sorted`.
# Results in $OUT/wide_step_sorted.tgz.
. docs/experiments/low_coverage/preamble.sh
REAL=$REAL_ENDS
for v in main step4 step4_sorted main; do bench $v real; done
for v in main step4 step4_sorted; do bench $v table3; done
cd $OUT && tar czf wide_step_sorted.tgz r && rm -rf r
