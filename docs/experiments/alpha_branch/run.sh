#!/usr/bin/env bash
# Table 3's scenes on `compute` with variants of the alpha branch in the traversal (BENCHMARKS.md,
# "Issue 20 on the H100"). Run at the repository root with a release binary as RAYGRAPH; the
# shader files are read at run time, so each variant is a patch applied to a copy of them.
set -euo pipefail
RAYGRAPH=${RAYGRAPH:-target/release/raygraph}
here=$(dirname "$0")
cp shaders/trace/compute.wgsl /tmp/compute.orig.wgsl; cp shaders/trace/alpha.wgsl /tmp/alpha.orig.wgsl
for v in orig notex noalpha v1 v2; do
    cp /tmp/compute.orig.wgsl shaders/trace/compute.wgsl; cp /tmp/alpha.orig.wgsl shaders/trace/alpha.wgsl
    [ "$v" != orig ] && patch -s -p0 < "$here/$v.patch"
    "$RAYGRAPH" bench rays --scenes box,organic,atrium --backend compute --frames 10 --out "/tmp/alpha-branch-$v" > /dev/null
    echo "$v: $(grep -E '^\| (box|organic|atrium|Miss|Stress) ' /tmp/alpha-branch-$v/rays.md | awk -F'|' '{printf "%s %s; ", $2, $7}')"
done
cp /tmp/compute.orig.wgsl shaders/trace/compute.wgsl; cp /tmp/alpha.orig.wgsl shaders/trace/alpha.wgsl
