#!/usr/bin/env bash
# Ablation behind delta-dag's README "What is left", 9×9 PCF: the kernel walk decoding each pack's
# code as it visits the pack (ca4a243) against decoding every code of a level in a pass of its own
# before visiting any (delta-dag-level-codes.patch on ca4a243), so that the level's first two
# loads per pack overlap. The layout is the same: each cell's structure is built once (city,
# terrain, tangle closed, the forest static and the city open at 16K²) and the two builds'
# `shadowbench bench --filters 1,9 --rounds 3` alternate on it four times; each line gives
# uniform 1×1, uniform 9×9, view 1×1 and view 9×9 in ns per query (one thread).
#   scripts/ablations/delta-dag-level-codes.sh [resolution, default 16K]
# shellcheck source=scripts/ablations/patched-build.sh
source "$(dirname "$0")/patched-build.sh"
resolution=${1:-16K}
build_at code-per-pack ca4a243
build_at codes-per-level ca4a243 delta-dag-level-codes.patch
alternate_on_cells "$resolution" code-per-pack codes-per-level
