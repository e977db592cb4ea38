#!/usr/bin/env bash
# Size of every lossless scheme side by side (issue 5): `sm32`, `compressed-sm`, `sm-zstd`,
# `openvdb`, `cpvs`, `cpvs-fast`, `mh`, `mmh`, `dag-mh` and `delta-dag` (issue 16), each at its registry defaults, on city
# and terrain, closed and open, 4K² to --max-resolution in MiB, beside the uncompressed float32
# map (4·R² bytes). Some cells are capped for memory (this machine: 2 cores, 24 GiB, shared; no
# cell may peak above about 16 GiB): `sm32` up to 16K² (4·R² bytes, which is the analytic row),
# `openvdb` up to 16K², `mh`, `mmh`, `dag-mh` and `delta-dag` open
# up to 8K² (a node per texel), the city open to 16K² (`delta-dag` to 32K², in parts); the caps are
# explained below and in the table. Also plots the
# same cells (scripts/plot.py) into results/reproduce/compare-size/plots.
#   scripts/reproduce/compare-size.sh [--max-resolution 256K] [sweep options]
# shellcheck source=scripts/reproduce/common.sh
source "$(dirname "$0")/common.sh"
scenes=city:full,terrain:full

# Caps (estimates from the records below the cap):
# - sm32 up to 16K²: the map is 4·R² bytes (4 GiB at 32K², 16 GiB at 64K²), exactly the analytic
#   row, so larger cells add nothing to a size table.
# - mh, mmh, dag-mh, delta-dag open up to 8K²: the ground is a point interval of changing depth, so the
#   hierarchy keeps about a node per texel (mh 70 MiB at 4K², ×4 per doubling) and mmh's build
#   peaks at 5.3 GiB at 8K² on city (1.6 GiB at 4K² on terrain, as on city): over 20 GiB at 16K².
# - openvdb up to 16K²: 3.7 GiB at 16K² on city closed and 4.5 GiB open, ×4.1 per doubling (no
#   subtree is shared, and every lower node touched holds a dense 33 KiB table), so about 15 and
#   18 GiB at 32K² and 60 GiB at 64K²; its encoder stops past 3/4 of the machine's memory.
up_to_16k=$(capped 16K 4K)
up_to_8k=$(capped 8K 4K)
sweep --schemes cpvs,cpvs-fast --scenes "$scenes" --modes closed,open \
  --resolutions "$(resolutions 4K)"
sweep --schemes mh,mmh,dag-mh,delta-dag --scenes "$scenes" --modes closed \
  --resolutions "$(resolutions 4K)"
sweep --schemes mh,mmh,dag-mh,delta-dag --scenes "$scenes" --modes open \
  --resolutions "$up_to_8k"
# The open city at 16K² too, a cell of issue 16's size goal: 7–9 GB a build (the terrain open
# holds a node per texel of ground and stays at 8K²).
city_open_16k=$(capped 16K 16K)
[ -z "$city_open_16k" ] || sweep --schemes mh,mmh,dag-mh,delta-dag --scenes city:full \
  --modes open --resolutions "$city_open_16k"
# And at 32K² for delta-dag alone, in parts of 8K²: its merge holds one part at a time (3.6 GiB),
# its MH part files take 12 GB; the other MH schemes' merges hold the whole hierarchy or more.
city_open_32k=$(capped 32K 32K)
[ -z "$city_open_32k" ] || sweep_part_size=8K sweep --schemes delta-dag --scenes city:full \
  --modes open --resolutions "$city_open_32k"
sweep --schemes sm-zstd --scenes "$scenes" --modes closed,open \
  --resolutions "$(resolutions 4K)"
sweep --schemes compressed-sm --scenes "$scenes" --modes closed,open --resolutions "$(resolutions 4K)"
sweep --schemes sm32 --scenes "$scenes" --modes closed,open --resolutions "$up_to_16k"
sweep --schemes openvdb --scenes "$scenes" --modes closed,open --resolutions "$up_to_16k"
# The same cells plotted, size and build time against resolution (one PNG pair per scene and
# mode the records hold), into results/reproduce/compare-size/plots.
/usr/bin/python3 scripts/plot.py "$records" --out "$out/$table/plots" \
  --schemes sm32,compressed-sm,sm-zstd,openvdb,cpvs,cpvs-fast,mh,mmh,dag-mh,delta-dag --defaults >/dev/null
tabulate
