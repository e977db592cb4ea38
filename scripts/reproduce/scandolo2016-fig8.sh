#!/usr/bin/env bash
# Scandolo et al. 2016 (MMH), Fig. 8: the size of `mmh` against its subtree-matching time for
# local search distances 0 … 10000, on city (≈ CLOSED CITY) closed, as a table beside `mh` (no
# merging) and the paper's Table 1 sizes. At 16K² (or --max-resolution if lower), not the
# paper's 64K²: there the 9 cells cost 2–3 minutes each plus a matching time that grows with the
# distance (about 25 minutes, a third of all-mh.sh) for a figure that prints no numbers;
# FIG8_RESOLUTION=64K builds the paper's. Distances other than 1000 are built --no-bench.
#   scripts/reproduce/scandolo2016-fig8.sh [--max-resolution 256K] [sweep options]
# shellcheck source=scripts/reproduce/common.sh
source "$(dirname "$0")/common.sh"
if ! at=$(texels "${FIG8_RESOLUTION:-16K}") || ((at < 8 || (at & (at - 1)) != 0)); then
  echo "$table: FIG8_RESOLUTION '$FIG8_RESOLUTION' must be a power of two such as 16K" >&2
  exit 2
fi
at=$(label $((at < max_texels ? at : max_texels)))
# Table 1's cells (mmh at its default search distance, the paper's 1000), with their lookup
# timings
sweep --schemes mh,mmh --scenes city:full --modes closed --resolutions "$at"
for distance in 0 10 100 250 500 2000 5000 10000; do
  sweep --schemes mmh --param search-distance=$distance --scenes city:full --modes closed \
    --resolutions "$at" --no-bench
done
tabulate
