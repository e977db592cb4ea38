#!/usr/bin/env bash
# Scandolo et al. 2016 (MMH), Table 1: the size of `mh`, `mmh` (search distance 1000) and `cpvs`
# (the paper's DAG) on city (≈ CLOSED CITY, CITYSCAPE), terrain (no counterpart) and forest
# (≈ VILLA, SHIP), closed, and on city open, at 4K², 16K², 64K² up to --max-resolution, with the
# paper's sizes beside ours. `cpvs` on forest is built up to 16K² only.
#   scripts/reproduce/scandolo2016-table1.sh [--max-resolution 64K] [sweep options]
# shellcheck source=scripts/reproduce/common.sh
source "$(dirname "$0")/common.sh"
mmh=(--param search-distance=1000)
sweep --schemes mh,mmh,cpvs "${mmh[@]}" --scenes city:full,terrain:full --modes closed \
  --resolutions "$(resolutions 4K 4)"
sweep --schemes mh,mmh,cpvs "${mmh[@]}" --scenes city:full --modes open \
  --resolutions "$(resolutions 4K 4)"
sweep --schemes mh,mmh "${mmh[@]}" --scenes forest:full --modes closed \
  --resolutions "$(resolutions 4K 4)"
# cpvs on forest at most 16K²: its voxel DAG grows fast (forest open at 64K²: 18 min, 6 GiB).
sweep --schemes cpvs --scenes forest:full --modes closed \
  --resolutions "$(max_texels=$((max_texels < 16384 ? max_texels : 16384)) && resolutions 4K 4)"
tabulate
