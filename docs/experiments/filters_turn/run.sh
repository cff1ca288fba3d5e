#!/usr/bin/env bash
# The shadows filtered as a visibility ratio and the temporal layer's consistent history taps,
# on the GPU machine: the hybrid_denoised frame before (.gpu/raygraph.gz, the build before the
# change, run from an empty folder so that it uses its own built-in graph, layers and shaders)
# and after (.gpu/raygraph-new.gz), alternating, two rounds, at 2560x1440 on the atrium; then
# `bench error --filters-only` (the full configuration: atrium and helmet at 1280x720) with the
# new binary. Results in $OUT/results.tgz (the frames' images left out).
set -u
for f in .gpu/gl/*.deb; do dpkg -x "$f" /; done
ldconfig
gunzip -c .gpu/raygraph.gz > /tmp/rg_old && gunzip -c .gpu/raygraph-new.gz > /tmp/rg_new && chmod +x /tmp/rg_old /tmp/rg_new
mkdir -p /tmp/empty /tmp/res
repo=$PWD
RES=/tmp/res
frame() { # binary, folder, label
    (cd "$2" && "$1" render --graph graph/hybrid_denoised.ron --scene atrium --width 2560 --height 1440 --frames 60 \
        --backend compute --report "$RES/$3" --out "/tmp/$3.png" > "$RES/$3.txt" 2>&1)
    tail -2 "$RES/$3/render.md"
}
frame /tmp/rg_new "$repo" warm_up > /dev/null
for round in 1 2; do
    echo "round $round before"; frame /tmp/rg_old /tmp/empty "before_$round"
    echo "round $round after"; frame /tmp/rg_new "$repo" "after_$round"
done
/tmp/rg_new bench error --filters-only --backend compute --out "$RES/filters" > "$RES/filters.log" 2>&1
tar czf "$OUT/results.tgz" -C "$RES" .
tail -n 14 "$RES/filters/filters.md"
