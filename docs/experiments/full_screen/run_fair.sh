#!/bin/bash
# PERF.md steps 54-55. Step 54: the rt-pipeline back-end's any-hit shader without the branch
# for closest-hit rays past BLEND surfaces in passes that trace no closest-hit rays
# (TRACE_CLOSEST_RAYS); this checkout as it is: `raygraph selftest`, then both back-ends on
# Table 3 and the real assets (the helmet, the pine and helmet_5x5x5 at their cameras and at 2%,
# 5%, 10% of the frame). Step 55 (diagnostic, compute): what is left of the tone map without its
# store (`tonemap_no_store`) and with every invocation but one returning at once
# (`tonemap_empty`), between two runs of main, on the helmet and the pine at their cameras and
# at 2% and 10%. Made by `bash docs/experiments/low_coverage/pack.sh af3dfd8
# docs/experiments/full_screen tonemap_no_store tonemap_empty`. Results in
# $OUT/fair_any_hit.tgz.
. docs/experiments/low_coverage/preamble.sh
shipped
REAL=$REAL_ENDS
for v in main tonemap_no_store tonemap_empty main; do bench $v real; done
cd $OUT && tar czf fair_any_hit.tgz r && rm -rf r
