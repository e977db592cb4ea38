#!/usr/bin/env bash
# Scandolo et al. 2016 (MMH), Table 2: the build time of `cpvs` (the paper's DAG), `mh` and `mmh`
# (search distance 1000), total and without the depth map, on city (≈ CLOSED CITY) closed at
# 4K², 16K², 64K² up to --max-resolution and on forest (≈ SHIP) closed up to 8K² (`cpvs` up to
# 16K²; scandolo2016-table1.sh says why), with the paper's times beside ours. The cells are
# Table 1's.
#   scripts/reproduce/scandolo2016-table2.sh [--max-resolution 64K] [sweep options]
# shellcheck source=scripts/reproduce/common.sh
source "$(dirname "$0")/common.sh"
# `resolutions` below a cap: capped CAP FIRST [STEP]
capped() {
  local cap max_texels=$max_texels
  cap=$(texels "$1")
  ((cap > max_texels)) || max_texels=$cap
  resolutions "${@:2}"
}
up_to_16k=$(capped 16K 4K 4)
up_to_8k=$(capped 8K 4K)
sweep --schemes mh,mmh,cpvs --param search-distance=1000 --scenes city:full --modes closed \
  --resolutions "$(resolutions 4K 4)"
sweep --schemes mh,mmh --param search-distance=1000 --scenes forest:full --modes closed \
  --resolutions "$up_to_8k"
sweep --schemes cpvs --scenes forest:full --modes closed --resolutions "$up_to_16k"
tabulate
