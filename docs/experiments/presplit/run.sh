#!/bin/bash
# PERF.md step 45 (CPU): triangles pre-split before the merged build (presplit.patch: a
# budgeted split of the triangles whose box exceeds what they need by the most, at power-of-two
# grid planes, after Karras and Aila 2013), counted by the CPU mirror of the traversal at
# budgets 0 to 1 extra reference a triangle: the scene workload (16 AO rays a pixel) and the
# scene camera's primary rays, on the pine, the helmet (every 16th pixel) and the atrium (every
# 32nd). Applies the patch to a worktree of HEAD in /tmp/presplit.
set -eu
cd "$(dirname "$0")/../../.."
rm -rf /tmp/presplit && git worktree prune && git worktree add -q --detach /tmp/presplit HEAD
patch -s -p1 -d /tmp/presplit < docs/experiments/presplit/presplit.patch
cd /tmp/presplit && cargo build -q --release --example presplit_count
for s in assets/gltf/smallpine/scene.gltf:16 assets/gltf/DamagedHelmet/DamagedHelmet.glb:16 atrium:32; do
  echo "## ${s%%:*}, every ${s##*:}th pixel, 16 AO rays"
  ./target/release/examples/presplit_count ${s%%:*} ${s##*:} 16
done
