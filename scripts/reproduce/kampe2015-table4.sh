#!/usr/bin/env bash
# Kämpe et al. 2015, Table 4: the total build time of `cpvs-fast` on city (≈ ClosedCity) and
# terrain (≈ FractalLandscape) open and closed and forest (≈ Necropolis) open, and of `cpvs`
# (Sintorn 2014) closed on city and terrain, from 4K² to --max-resolution, with the paper's
# times beside ours.
#   scripts/reproduce/kampe2015-table4.sh [--max-resolution 256K] [sweep options]
# shellcheck source=scripts/reproduce/common.sh
source "$(dirname "$0")/common.sh"
sweep --schemes cpvs-fast --scenes city:full,terrain:full --modes open,closed \
  --resolutions "$(resolutions 4K)"
sweep --schemes cpvs-fast --scenes forest:full --modes open --resolutions "$(resolutions 4K)"
sweep --schemes cpvs --scenes city:full,terrain:full --modes closed --resolutions "$(resolutions 4K)"
tabulate
