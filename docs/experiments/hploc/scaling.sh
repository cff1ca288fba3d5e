#!/bin/bash
# How the H-PLOC build's phases grow with the triangle count: `bench build --scenes atrium
# --max-factor 3` (the atrium copied 1, 2 and 3 times per axis without instancing: 262k, 2.1M
# and 7.1M triangles), release binary .gpu/raygraph, from an empty folder. Whether a fixed part
# (the climb's chain of levels to the root) or the work per triangle sets the tree kernel's
# 0.34 ms at 262k. Prints the table last.
set -u
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
gunzip -f .gpu/raygraph.gz; chmod +x .gpu/raygraph
RG=$PWD/.gpu/raygraph; OUT=${OUT:-/tmp/out}; mkdir -p $OUT/r /tmp/empty
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
(cd /tmp/empty && timeout 450 $RG bench build --scenes atrium --max-factor 3 --out $OUT/r/build > $OUT/r/build.log 2>&1) || tail -3 $OUT/r/build.log
cd $OUT && tar czf results.tgz r && cat r/build/*.md | grep -E "^\|" | cut -c1-260
