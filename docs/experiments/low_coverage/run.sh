#!/bin/bash
# PERF.md step 32: what the real assets' passes spend at low coverage, on the GPU machine. Main's
# files and three variants of them (.gpu/diag.tgz, made by pack.sh from variants/): `alpha_off`
# (the compute traversal without the alpha test: every alpha-tested candidate kept, an upper
# bound on what the test costs), `alpha_twice` (the alpha texture read a second time per
# candidate, folded in by a weight that is 0 at run time: a lower bound on one read's cost, its
# texels already in L1) and `shadow_notrace` (the shadow pass without its rays: light reaches
# every point that faces it). The helmet and the pine at their cameras and at 2%, 5%, 10% of the
# frame, `bench rays --frames 10`: main on both back-ends first, the variants and main again on
# `compute`. One release binary (.gpu/raygraph.xz). Results in $OUT/low_coverage.tgz.
. docs/experiments/low_coverage/preamble.sh
for name in main ${VARIANTS:-alpha_off alpha_twice shadow_notrace} main; do
  n=$name; args="--backend compute"
  if [ -d $OUT/r/$n ]; then n=${name}_2; elif [ $name = main ]; then args=""; fi
  if [ $SECONDS -gt ${DEADLINE:-480} ]; then echo "deadline: $n skipped"; continue; fi
  (cd /tmp/v/$name && timeout 200 $RG bench rays $REAL $args --frames 10 --out $OUT/r/$n > $OUT/r/$n.log 2>&1) || tail -2 $OUT/r/$n.log
  echo "== $n ($SECONDS s)"; grep -E "^\| " $OUT/r/$n/rays.md | grep -v -- "---" | grep -v " test |" | awk -F'|' '{print $2 "|" $3 "|" $5 "|" $6}' | sed 's|/[^ ]*/||'
done
cd $OUT && tar czf low_coverage.tgz r && rm -rf r
