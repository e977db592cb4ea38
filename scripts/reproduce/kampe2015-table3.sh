#!/usr/bin/env bash
# Kämpe et al. 2015, Table 3: the build time of `cpvs-fast` by step (depth map, visibility
# masks, min-max, insert, merge) on city (≈ ClosedCity) open and closed, at 4K², 16K², 64K² up to
# --max-resolution, with the paper's times beside ours.
#   scripts/reproduce/kampe2015-table3.sh [--max-resolution 256K] [sweep options]
# shellcheck source=scripts/reproduce/common.sh
source "$(dirname "$0")/common.sh"
sweep --schemes cpvs-fast --scenes city:full --modes open,closed --resolutions "$(resolutions 4K 4)"
tabulate
