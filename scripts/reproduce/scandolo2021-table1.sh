#!/usr/bin/env bash
# Scandolo & Eisemann 2021 (DAG-MH), Table 1: the size of `cpvs` (the paper's DAG), `mmh` (search
# distance 1000) and `dag-mh` (treelets of 4, chunks of 32) on city (≈ Citadel, City) closed from
# 4K² to --max-resolution, and on terrain (no counterpart), forest (≈ Trees) and tangle
# (≈ Hairball) closed and city open at 4K², 16K², 64K², beside the uncompressed 32-bit map and the
# paper's sizes. `cpvs` on forest and tangle is built up to 16K² only.
#   scripts/reproduce/scandolo2021-table1.sh [--max-resolution 64K] [sweep options]
# shellcheck source=scripts/reproduce/common.sh
source "$(dirname "$0")/common.sh"
defaults=(--param search-distance=1000 --param treelet-height=4 --param chunk-size=32
  --param skip-level=6)
sweep --schemes mmh,dag-mh,cpvs "${defaults[@]}" --scenes city:full --modes closed \
  --resolutions "$(resolutions 4K)"
sweep --schemes mmh,dag-mh,cpvs "${defaults[@]}" --scenes terrain:full --modes closed \
  --resolutions "$(resolutions 4K 4)"
sweep --schemes mmh,dag-mh,cpvs "${defaults[@]}" --scenes city:full --modes open \
  --resolutions "$(resolutions 4K 4)"
sweep --schemes mmh,dag-mh "${defaults[@]}" --scenes forest:full,tangle:full --modes closed \
  --resolutions "$(resolutions 4K 4)"
# cpvs on forest and tangle at most 16K²: its voxel DAG grows fast (forest open at 64K²: 18 min,
# 6 GiB).
sweep --schemes cpvs --scenes forest:full,tangle:full --modes closed \
  --resolutions "$(max_texels=$((max_texels < 16384 ? max_texels : 16384)) && resolutions 4K 4)"
tabulate
