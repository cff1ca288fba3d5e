#!/bin/bash
# `bench anim` on the H100 after the cost policy (BENCHMARKS.md, "Animation"): the same scenes,
# size and frames as run.sh, compute back-end, policies auto x1.1 (the threshold run.sh chose),
# cost, always refit, always rebuild. Run with carry [".gpu"].
for f in .gpu/gl/*.deb; do dpkg -x $f /; done; ldconfig
R=$PWD/.gpu/raygraph
$R bench anim --scenes organic-skinned,atrium-moving --frames 240 --max-growth 1.1 --out $OUT/cost >/tmp/cost.log 2>&1 || tail -5 /tmp/cost.log
grep "^|" $OUT/cost/anim.md | cut -d'|' -f2-13
