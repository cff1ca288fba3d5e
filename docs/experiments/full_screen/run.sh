#!/bin/bash
# PERF.md step 52: what the passes cost over the whole image where few pixels are covered.
# Variants (diagnostic; made by `bash docs/experiments/low_coverage/pack.sh 959bde6
# docs/experiments/full_screen wg16 trace_wg16 sky_position_only tonemap_write_only
# shadow_sky_nowrite`): `wg16` the resolve and tone-map passes in 16x16 workgroups (8x8 in
# main); `trace_wg16` the primary and shadow passes likewise; `sky_position_only` the G-buffer
# of a sky pixel written to `position` alone; `tonemap_write_only` the tone map reading one
# texel for every pixel; `shadow_sky_nowrite` the shadow pass writing nothing on the sky. On the
# GPU machine, one release binary (.gpu/raygraph.xz): `bench rays --backend compute --frames
# 10` on the helmet and the pine at their cameras and at 2% and 10% of the frame, for main,
# each variant, and main again. Results in $OUT/full_screen.tgz.
. docs/experiments/low_coverage/preamble.sh
REAL=$REAL_ENDS
for v in main wg16 trace_wg16 sky_position_only tonemap_write_only shadow_sky_nowrite main; do bench $v real; done
cd $OUT && tar czf full_screen.tgz r && rm -rf r
