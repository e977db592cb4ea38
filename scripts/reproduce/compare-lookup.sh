#!/usr/bin/env bash
# Lookup cost of every lossless scheme side by side (issues 5 and 13): ns per query on one thread
# of `sm32`, `compressed-sm`, `sm-zstd`, `openvdb`, `cpvs`, `cpvs-fast`, `mh`, `mmh`, `dag-mh` and
# `delta-dag`,
# each at its registry defaults, for point lookups (1×1) and 3×3, 5×5, 9×9 and 17×17 PCF, each
# over the point lookup, uniform (random) and view queries, with the size beside them, on city,
# terrain and tangle closed and forest static at 4K², 16K², 64K² up to --max-resolution, with
# the papers' lookup figures beside (64K² at most). Its own records folder (results/reproduce/compare-lookup/
# records): timings are of the code that built them, so after a change to a lookup, delete the
# folder and run again. Caps for memory: `sm32` up to 16K² (4·R² bytes), `openvdb` up to 16K²
# and on city and terrain only (compare-size.sh says why).
#   scripts/reproduce/compare-lookup.sh [--max-resolution 256K] [sweep options]
# shellcheck source=scripts/reproduce/common.sh
source "$(dirname "$0")/common.sh"
records=$out/$table/records
# 4K², 16K² and 64K² at most: the lookup goals are set there, and 256K² cells belong to the
# paper tables (hours each).
up_to_64k=$(capped 64K 4K 4)
up_to_16k=$(capped 16K 4K 4)
for build in "city:full closed" "terrain:full closed" "tangle:full closed" "forest:full static"; do
  read -r scene mode <<<"$build"
  sweep --schemes cpvs,cpvs-fast,mh,mmh,dag-mh,delta-dag,compressed-sm,sm-zstd --scenes "$scene" \
    --modes "$mode" --resolutions "$up_to_64k"
  case $scene in
    city:* | terrain:*) small=sm32,openvdb ;;
    *) small=sm32 ;;
  esac
  sweep --schemes "$small" --scenes "$scene" --modes "$mode" --resolutions "$up_to_16k"
done
tabulate
