#!/usr/bin/env bash
# Ablation behind delta-dag's README "Planar nodes, measured before building them": what a
# quadtree of planes would take. Commit cd1ac67 with delta-dag-planar-potential.patch: the encode
# step codes the map as a quadtree from 64×64 blocks, each split or a plane in key space (its key
# and two slopes, 64 bits, and the residual's width) with per texel the residual of fewest bits
# that lands inside the texel's interval, and prints one PLANAR line per build (its size, and the
# residual widths of the 8×8 blocks' planes); it is not a scheme parameter. Beside it, the
# structure delta-dag builds of the same cell.
#   scripts/ablations/delta-dag-planar-potential.sh [resolution, default 4K]
# shellcheck source=scripts/ablations/patched-build.sh
source "$(dirname "$0")/patched-build.sh"
resolution=${1:-4K}
build_at planar cd1ac67 delta-dag-planar-potential.patch
sb=$work/planar-build/harness/shadowbench
for build in "city:full open" "terrain:full open" "city:full closed" "terrain:full closed"; do
  read -r scene mode <<<"$build"
  out=$("$sb" build --scheme delta-dag -s "$scene" -m "$mode" -r "$resolution" --no-bench \
    --no-verify --results "$work/records" 2>&1)
  echo "$resolution $scene $mode: delta-dag $(grep -oE "[0-9.]+ MiB in" <<<"$out" | cut -d' ' -f1-2);" \
    "$(grep PLANAR <<<"$out")"
done
