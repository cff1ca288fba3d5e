#!/bin/bash
# PERF.md step 35: fewer values live in the traversal loops (variants/*.patch, the same images):
# `merged_path`, the merged layout's one instance traversed without the two-level loop, so the
# world ray is not kept beside the instance's; `start_extent`, the AO start's box formed from
# its centre and extent where it is tested instead of carried across a pixel's rays;
# `rows_at_leaf`, the watertight test's shear rows formed at each leaf from the direction
# instead of carried through the interior steps; `merged_extent` the first two, `all` the
# three. Made by `bash docs/experiments/low_coverage/pack.sh REV docs/experiments/live_state
# all merged_path start_extent rows_at_leaf merged_extent`. `bench rays --backend compute
# --frames 10`: Table 3 for every variant, the real assets (the helmet, the pine, at their
# cameras and at 2%, 5%, 10% of the frame) for main, `all` and `merged_extent`; main first and
# last. One release binary (.gpu/raygraph.xz). Results in $OUT/live_state.tgz.
. docs/experiments/low_coverage/preamble.sh
bench main table3; bench main real
bench all table3; bench all real
for v in merged_path start_extent rows_at_leaf merged_extent; do bench $v table3; done
bench merged_extent real
bench main table3; bench main real
cd $OUT && tar czf live_state.tgz r && rm -rf r
