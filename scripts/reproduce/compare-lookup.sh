#!/usr/bin/env bash
# Lookup cost of every lossless scheme side by side (issue 5): ns per query on one thread of
# `sm32`, `compressed-sm`, `sm-zstd`, `openvdb`, `cpvs`, `cpvs-fast`, `mh`, `mmh` and `dag-mh`,
# each at its registry defaults, for point lookups (1×1) and 9×9 PCF, uniform (the issue's random
# queries) and view queries, with the size beside them, on city closed and terrain closed at
# 4K², 16K², 64K² up to --max-resolution, and every other cell with timings the records folder
# holds (compare-size.sh builds open mode and the resolutions between). The cells are those
# compare-size.sh builds, with its memory caps: `sm32` and `openvdb` up to 16K² (so at 4K² and
# 16K² here).
#   scripts/reproduce/compare-lookup.sh [--max-resolution 256K] [sweep options]
# shellcheck source=scripts/reproduce/common.sh
source "$(dirname "$0")/common.sh"
scenes=city:full,terrain:full
# compare-size.sh says why these caps (memory: no cell above about 16 GiB).
up_to_16k=$(capped 16K 4K 4)
sweep --schemes cpvs,cpvs-fast --scenes "$scenes" --modes closed \
  --resolutions "$(resolutions 4K 4)"
sweep --schemes mh,mmh,dag-mh --scenes "$scenes" --modes closed \
  --resolutions "$(resolutions 4K 4)"
sweep --schemes sm-zstd --scenes "$scenes" --modes closed \
  --resolutions "$(resolutions 4K 4)"
sweep --schemes compressed-sm --scenes "$scenes" --modes closed --resolutions "$(resolutions 4K 4)"
sweep --schemes sm32 --scenes "$scenes" --modes closed --resolutions "$up_to_16k"
sweep --schemes openvdb --scenes "$scenes" --modes closed --resolutions "$up_to_16k"
tabulate
