#!/usr/bin/env bash
# Lookup cost by filter size (Sintorn et al. 2014 §7, "Evaluation performance"): ns per query of
# `cpvs` and `cpvs-fast` at 1×1, 9×9 and 17×17 and the ratios 9×9/1×1 and 17×17/1×1, uniform and
# view queries, on city (≈ ClosedCity) closed and open and forest (≈ Necropolis) open, at 4K²,
# 16K², 64K² up to --max-resolution; `sm32` (float32 shadow map, at most 16K²) for reference.
#   scripts/reproduce/cpvs-lookup.sh [--max-resolution 256K] [sweep options]
# shellcheck source=scripts/reproduce/common.sh
source "$(dirname "$0")/common.sh"
for scene_modes in "city:full closed,open" "forest:full open"; do
  read -r scene modes <<<"$scene_modes"
  sweep --schemes cpvs,cpvs-fast --scenes "$scene" --modes "$modes" \
    --resolutions "$(resolutions 4K 4)"
done
# sm32 is the reference only, up to 16K²: a 64K² float map is 16 GiB.
sm32_resolutions=$(max_texels=$((max_texels < 16384 ? max_texels : 16384)) && resolutions 4K 4)
sweep --schemes sm32 --scenes city:full --modes closed,open --resolutions "$sm32_resolutions"
tabulate
