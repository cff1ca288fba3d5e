#!/bin/bash
# PERF.md step 31: two operations fewer per interior step, on main's files (1f35499) and the
# release binary of 6276040: `lea`, a descriptor as a shift and an add instead of a shift and an
# OR; `lea_nocheck`, the same without the push's explicit bound check (naga's clamp of the
# stack index stays). Made here by `bash docs/experiments/step_cost/pack.sh
# docs/experiments/step_ops lea lea_nocheck`; run by step_cost's script (Table 3, compute,
# main first and last). Results in $OUT/step_cost.tgz.
VARIANTS="lea lea_nocheck" bash docs/experiments/step_cost/run.sh
