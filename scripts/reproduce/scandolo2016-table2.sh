#!/usr/bin/env bash
# Scandolo et al. 2016 (MMH), Table 2: the build time of `cpvs` (the paper's DAG), `mh` and `mmh`
# (search distance 1000), total and without the depth map, on city (≈ CLOSED CITY) closed at
# 4K², 16K², 64K² up to --max-resolution and on forest (≈ SHIP) static likewise, with the
# paper's times beside ours. The cells are Table 1's.
#   scripts/reproduce/scandolo2016-table2.sh [--max-resolution 256K] [sweep options]
# shellcheck source=scripts/reproduce/common.sh
source "$(dirname "$0")/common.sh"
sweep --schemes mh,mmh,cpvs,cpvs-fast --scenes city:full --modes closed \
  --resolutions "$(resolutions 4K 4)"
sweep --schemes mh,mmh,cpvs,cpvs-fast --scenes forest:full --modes static \
  --resolutions "$(resolutions 4K 4)"
tabulate
