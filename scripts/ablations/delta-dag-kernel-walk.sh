#!/usr/bin/env bash
# Ablation behind delta-dag's README "Kernels level by level": the kernel walk depth first
# (c6c4a4b), depth first with a texel pack's children read without a step each (c6c4a4b with
# delta-dag-texel-children.patch) and level by level with both (e1f42c5). The layout is the
# same, so each cell's structure is built once (city, terrain, tangle closed, the forest static
# and the city open at 16K²) and the three builds' `shadowbench bench --filters 1,9 --rounds 3`
# alternate on it four times; each line gives uniform 1×1, uniform 9×9, view 1×1 and view 9×9 in
# ns per query (one thread).
#   scripts/ablations/delta-dag-kernel-walk.sh [resolution, default 16K]
# shellcheck source=scripts/ablations/patched-build.sh
source "$(dirname "$0")/patched-build.sh"
resolution=${1:-16K}
build_at depth-first c6c4a4b
build_at texel-children c6c4a4b delta-dag-texel-children.patch
build_at level-by-level e1f42c5
alternate_on_cells "$resolution" depth-first texel-children level-by-level
