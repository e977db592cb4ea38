#!/usr/bin/env bash
# What a part border costs (issue 12, DESIGN §5): each compressed scheme — cpvs, cpvs-fast, mh,
# mmh, dag-mh, compressed-sm — built whole and in 16 parts (parts of R/4) at 16K² and 64K² (up to
# --max-resolution) on city and terrain closed and forest static: size whole and in parts and
# their difference, build time, peak RSS and the declared memory estimate beside it. Both
# builds are verified (sampled); the merged structure answers as the whole build by construction
# (tests/parts_test.cpp checks every texel at small sizes).
#   scripts/reproduce/parts-cost.sh [--max-resolution 256K] [sweep options] (64K² at most)
# shellcheck source=scripts/reproduce/common.sh
source "$(dirname "$0")/common.sh"
# Its own records folder: the paper tables' keep one record per cell, whole or in parts.
records=$out/$table/records
schemes=cpvs,cpvs-fast,mh,mmh,dag-mh,compressed-sm
for build in "city:full closed" "terrain:full closed" "forest:full static"; do
  read -r scene mode <<<"$build"
  for r in $(capped 64K 16K 4 | tr , ' '); do
    sweep_part_size=whole sweep --schemes "$schemes" --scenes "$scene" --modes "$mode" \
      --resolutions "$r" --no-bench
    sweep_part_size=$(label $(($(texels "$r") / 4))) sweep --schemes "$schemes" \
      --scenes "$scene" --modes "$mode" --resolutions "$r" --no-bench
  done
done
tabulate
