#!/bin/bash
# Per-triangle alpha maps (the idea of opacity micromaps: 64 micro-triangles a triangle, each
# known below the cutoff, full, or unknown, so that a candidate in a known one skips the texture
# read), measured on the CPU before any GPU work: how much of the pine's foliage the maps know.
# Applies alpha_map.patch to a scratch worktree of the commit it was written against and runs
# its test, which checks every known state against the CPU's alpha test at 64 random points of
# every alpha-tested triangle and prints the share known; then again with the margin of a
# bilinear read only (2 texels, no allowance for the 256x256 texture-array fallback), the most
# the maps could know at 64 micro-triangles. No GPU; the build goes to target/alpha_map_experiment (a full build the first time).
set -eu
ROOT=$(git rev-parse --show-toplevel)
W=$(mktemp -d)/alpha_map
git -C "$ROOT" worktree add -q "$W" c96385b
cd "$W"
export CARGO_TARGET_DIR="$ROOT/target/alpha_map_experiment"
git apply "$ROOT/docs/experiments/alpha_map/alpha_map.patch"
cargo test --test alpha alpha_maps -- --nocapture 2>&1 | grep -E "known by the maps" || true
sed -i 's/    let margin = 2.0 \* (w.max(h) \/ FALLBACK_SIZE).max(1.0).ceil() + 2.0;/    let margin = 2.0 + 0.0 * FALLBACK_SIZE;/' src/accel/alpha_map.rs
cargo test --test alpha alpha_maps -- --nocapture 2>&1 | grep -E "known by the maps" || true
cd "$ROOT" && git worktree remove --force "$W"
