#!/bin/bash
# PERF.md step 54: the rt-pipeline back-end's any-hit shader without the branch for closest-hit
# rays past BLEND surfaces in passes that trace no closest-hit rays (TRACE_CLOSEST_RAYS). On the
# GPU machine, this checkout as it is: `raygraph selftest`, then both back-ends on Table 3 and the
# real assets (the helmet, the pine and helmet_5x5x5 at their cameras and at 2%, 5%, 10% of the
# frame). .gpu/diag.tgz is unpacked but not used. Results in $OUT/fair_any_hit.tgz.
. docs/experiments/low_coverage/preamble.sh
shipped
cd $OUT && tar czf fair_any_hit.tgz r && rm -rf r
