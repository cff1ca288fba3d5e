#!/bin/bash
# PERF.md step 53: the resolve, the tone map and the four-lane AO sum in 16x16 workgroups (this
# checkout as it is: `raygraph selftest`, then both back-ends on Table 3 and the real assets),
# and two diagnostic variants with more pixels an invocation (`block2`, `block4`: the resolve
# and the tone map with two and four pixels an invocation, the dispatch fixed to 2560x1440),
# compute only, between two runs of main, on the helmet and the pine at their cameras and at 2%
# and 10% of the frame. Made by `bash docs/experiments/low_coverage/pack.sh 11bb2e4
# docs/experiments/full_screen block2 block4`. Results in $OUT/full_screen_product.tgz.
. docs/experiments/low_coverage/preamble.sh
shipped
REAL=$REAL_ENDS
for v in main block2 block4 main; do bench $v real; done
cd $OUT && tar czf full_screen_product.tgz r && rm -rf r
