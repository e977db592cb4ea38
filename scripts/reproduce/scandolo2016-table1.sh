#!/usr/bin/env bash
# Scandolo et al. 2016 (MMH), Table 1: the size of `mh`, `mmh` (search distance 1000) and `cpvs`
# (the paper's DAG) on city (≈ CLOSED CITY, CITYSCAPE) and terrain (no counterpart) closed at
# 4K², 16K², 64K² up to --max-resolution, and on forest (≈ VILLA, SHIP) closed and city open up
# to 8K² (`cpvs` on forest up to 16K²), with the paper's sizes beside ours.
#   scripts/reproduce/scandolo2016-table1.sh [--max-resolution 64K] [sweep options]
# shellcheck source=scripts/reproduce/common.sh
source "$(dirname "$0")/common.sh"
# Caps: cpvs on forest up to 16K², as its voxel DAG grows fast there (forest open at 64K²: 18
# minutes, 6 GiB). The MH family on city open and forest closed up to 8K²: their ground is a
# point interval of changing depth, so about a node per texel (mh 70 MiB at 4K², ×4 per
# doubling; mmh peaks at 1.3 GiB at 4K², ~20 GiB at 16K²).
# `resolutions` below a cap: capped CAP FIRST [STEP]
capped() {
  local cap max_texels=$max_texels
  cap=$(texels "$1")
  ((cap > max_texels)) || max_texels=$cap
  resolutions "${@:2}"
}
up_to_16k=$(capped 16K 4K 4)
up_to_8k=$(capped 8K 4K)
mmh=(--param search-distance=1000)
sweep --schemes mh,mmh,cpvs "${mmh[@]}" --scenes city:full,terrain:full --modes closed \
  --resolutions "$(resolutions 4K 4)"
sweep --schemes mh,mmh,cpvs "${mmh[@]}" --scenes city:full --modes open --resolutions "$up_to_8k"
sweep --schemes mh,mmh "${mmh[@]}" --scenes forest:full --modes closed --resolutions "$up_to_8k"
sweep --schemes cpvs --scenes forest:full --modes closed --resolutions "$up_to_16k"
tabulate
