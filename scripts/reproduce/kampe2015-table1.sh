#!/usr/bin/env bash
# Kämpe et al. 2015, Table 1: the build time of `cpvs-fast` with and without the culling of
# identical nodes (total, and insert + merge), on city (≈ ClosedCity) open and closed, from 4K²
# to --max-resolution, with the paper's times beside ours.
#   scripts/reproduce/kampe2015-table1.sh [--max-resolution 256K] [sweep options]
# shellcheck source=scripts/reproduce/common.sh
source "$(dirname "$0")/common.sh"
for culling in on off; do
  sweep --schemes cpvs-fast --param culling=$culling --scenes city:full --modes open,closed \
    --resolutions "$(resolutions 4K)"
done
tabulate
