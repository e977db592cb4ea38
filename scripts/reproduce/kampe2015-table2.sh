#!/usr/bin/env bash
# Kämpe et al. 2015, Table 2: the size of `cpvs` ("old", Sintorn 2014) and `cpvs-fast` ("new")
# with the closed-object optimisation, and their ratio, on city (≈ ClosedCity) and terrain
# (≈ FractalLandscape), from 4K² to --max-resolution, with the paper's sizes beside ours. `new`
# twice: coarse volumes classified by the visibility masks' pyramid (the default) and by the
# min-max hierarchy of the enter and exit depth maps, as the paper does
# (coarse-classification=depth-hierarchy, --no-bench: only its size is tabulated).
#   scripts/reproduce/kampe2015-table2.sh [--max-resolution 256K] [sweep options]
# shellcheck source=scripts/reproduce/common.sh
source "$(dirname "$0")/common.sh"
sweep --schemes cpvs,cpvs-fast --scenes city:full,terrain:full --modes closed \
  --resolutions "$(resolutions 4K)"
sweep --schemes cpvs-fast --param coarse-classification=depth-hierarchy \
  --scenes city:full,terrain:full --modes closed --resolutions "$(resolutions 4K)" --no-bench
tabulate
