#!/usr/bin/env bash
# Sintorn et al. 2014, Fig. 9: the size of `cpvs` (MiB and % of a 16-bit shadow map) from 1K² to
# --max-resolution, on city (≈ ClosedCity) and terrain (≈ FractalLandscape), closed and open,
# and forest (≈ Necropolis) open and static, with the paper's sizes beside ours.
#   scripts/reproduce/sintorn2014-fig9.sh [--max-resolution 256K] [sweep options]
# shellcheck source=scripts/reproduce/common.sh
source "$(dirname "$0")/common.sh"
sweep --schemes cpvs --scenes city:full,terrain:full --modes closed,open \
  --resolutions "$(resolutions 1K)"
sweep --schemes cpvs --scenes forest:full --modes open,static --resolutions "$(resolutions 1K)"
tabulate
