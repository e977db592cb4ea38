#!/usr/bin/env bash
# Scandolo et al. 2016 (MMH), Fig. 8: the size of `mmh` against its subtree-matching time for
# local search distances 0 … 10000, on city (≈ CLOSED CITY) closed at --max-resolution (the
# paper's 64K²), as a table beside `mh` (no merging) and the paper's sizes at distance 1000.
# The distances other than 1000 are built without lookup timings (--no-bench).
#   scripts/reproduce/scandolo2016-fig8.sh [--max-resolution 64K] [sweep options]
# shellcheck source=scripts/reproduce/common.sh
source "$(dirname "$0")/common.sh"
at=$(label "$max_texels")
# Table 1's cells, with their lookup timings
sweep --schemes mh,mmh --param search-distance=1000 --scenes city:full --modes closed \
  --resolutions "$at"
for distance in 0 10 100 250 500 2000 5000 10000; do
  sweep --schemes mmh --param search-distance=$distance --scenes city:full --modes closed \
    --resolutions "$at" --no-bench
done
tabulate
