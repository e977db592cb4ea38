#!/usr/bin/env bash
# Scandolo & Eisemann 2021 (DAG-MH), Table 3: the DAG structure of `dag-mh` (its size, inner
# nodes, treelets) for treelet heights 2, 3, 4, 5, on city (≈ Citadel) closed at 16K² and 64K² up
# to --max-resolution, with the paper's figures beside ours. Heights other than 4 are built
# without lookup timings (--no-bench).
#   scripts/reproduce/scandolo2021-table3.sh [--max-resolution 256K] [sweep options]
# shellcheck source=scripts/reproduce/common.sh
source "$(dirname "$0")/common.sh"
for height in 4 2 3 5; do
  bench=()
  [ $height = 4 ] || bench=(--no-bench) # height 4 is Table 1's cell
  sweep --schemes dag-mh --param treelet-height=$height --scenes city:full --modes closed \
    --resolutions "$(resolutions 16K 4)" "${bench[@]}"
done
tabulate
