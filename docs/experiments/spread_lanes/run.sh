#!/bin/bash
# PERF.md step 48: how many lanes share a listed pixel's AO rays in the spread schedule
# (shaders/common/ao_lane_count.wgsl). Main aims at one (pixel, lane) item an image pixel; the
# variants at a quarter, an eighth and a sixteenth of that (`items_quarter`, `items_eighth`,
# `items_sixteenth`: the same rays and samples, fewer lanes a pixel, more rays a lane). On the
# GPU machine, one release binary (.gpu/raygraph.xz): `bench rays --backend compute --frames
# 10` on the real assets (the helmet, the pine and helmet_5x5x5 at their cameras and at 2%, 5%,
# 10% of the frame) for main, the three variants and main again. Made by `bash
# docs/experiments/low_coverage/pack.sh REV docs/experiments/spread_lanes items_quarter
# items_eighth items_sixteenth`. Results in $OUT/spread_lanes.tgz.
. docs/experiments/low_coverage/preamble.sh
export_copies
REAL=$REAL_ALL
for v in main items_quarter items_eighth items_sixteenth main; do bench $v real; done
cd $OUT && tar czf spread_lanes.tgz r && rm -rf r
