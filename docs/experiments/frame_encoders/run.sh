#!/bin/bash
# The frame recorded into several encoders finished in parallel (src/runtime/exec/commands.rs
# of commit 495c5d3, taken out after this run: build .gpu/raygraph from that commit) against
# one encoder finished at submission (RAYGRAPH_FRAME_ENCODERS=1), one binary, one
# session: `render --report` (2560x1440, 60 frames, `compute`) of the five built-in graphs on
# the atrium copied 1 and 3 times per axis (262k and 7.1M unique triangles), one encoder and
# the default one after the other for each row; then full RT and raster on 5 copies per axis
# (32.8M). Results under $OUT (results.tgz), the `outside the passes` lines printed last.
set -u
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
gunzip -f .gpu/raygraph.gz && chmod +x .gpu/raygraph
RG=$PWD/.gpu/raygraph
OUT=${OUT:-/tmp/out}; mkdir -p $OUT/r/static /tmp/run
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv,noheader
nproc
rep() { local name=$1 encoders=$2 graph=$3; shift 3
  echo "== $name graph/$graph.ron encoders<=$encoders $*" >> $OUT/r/static.txt
  (cd /tmp/run && RAYGRAPH_FRAME_ENCODERS=$encoders timeout 120 $RG render --graph graph/$graph.ron "$@" --backend compute --width 2560 --height 1440 --frames 60 --report $OUT/r/static/$name --out /tmp/o.png 2>&1 | grep -E "^total|frame wall|outside the passes|rror" >> $OUT/r/static.txt); }
for dup in 1 3; do for g in raster hybrid hybrid_denoised full_rt ao; do
  copies=""; [ $dup = 1 ] || copies="--duplicate $dup --no-dedup"
  rep one_${g}_$dup 1 $g --scene atrium $copies
  rep four_${g}_$dup 4 $g --scene atrium $copies
done; done
for g in full_rt raster; do for e in 1 4; do rep e${e}_${g}_5 $e $g --scene atrium --duplicate 5 --no-dedup; done; done
cd $OUT && tar czf results.tgz r
grep -E "^==|frame wall|outside" r/static.txt | sed -e 's/outside the passes (medians): //'
rm -rf r
