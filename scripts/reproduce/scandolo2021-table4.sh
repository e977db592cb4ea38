#!/usr/bin/env bash
# Scandolo & Eisemann 2021 (DAG-MH), Table 4: the depth values of `dag-mh` (chunk map and factor
# sizes, values needing a factor, bits per factor) for 16, 32, 64, 128 values per chunk, on city
# (≈ Citadel) closed at 16K² and 64K² up to --max-resolution, with the paper's figures beside
# ours. Chunk sizes other than 32 are built without lookup timings (--no-bench).
#   scripts/reproduce/scandolo2021-table4.sh [--max-resolution 256K] [sweep options]
# shellcheck source=scripts/reproduce/common.sh
source "$(dirname "$0")/common.sh"
for chunk in 32 16 64 128; do
  bench=()
  [ $chunk = 32 ] || bench=(--no-bench) # 32 is Table 1's cell
  sweep --schemes dag-mh --param chunk-size=$chunk --scenes city:full --modes closed \
    --resolutions "$(resolutions 16K 4)" "${bench[@]}"
done
tabulate
