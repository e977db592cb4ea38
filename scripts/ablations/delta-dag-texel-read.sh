#!/usr/bin/env bash
# Ablation behind delta-dag's README "Texel packs in one read": the kernel walk reading each
# overlapped texel's value from its own field (02eab94) against cutting a texel pack's four values
# from one read where they fit 57 bits (b3eccaf). The layout is the same, so each cell's structure
# is built once (city, terrain, tangle closed, the forest static and the city open at 16K²) and
# the two builds' `shadowbench bench --filters 1,9 --rounds 3` alternate on it four times; each
# line gives uniform 1×1, uniform 9×9, view 1×1 and view 9×9 in ns per query (one thread).
#   scripts/ablations/delta-dag-texel-read.sh [resolution, default 16K]
# shellcheck source=scripts/ablations/patched-build.sh
source "$(dirname "$0")/patched-build.sh"
resolution=${1:-16K}
build_at field-per-texel 02eab94
build_at one-read b3eccaf
alternate_on_cells "$resolution" field-per-texel one-read
