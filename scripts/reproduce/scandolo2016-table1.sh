#!/usr/bin/env bash
# Scandolo et al. 2016 (MMH), Table 1: the size of `mh`, `mmh` (search distance 1000) and `cpvs`
# (the paper's DAG) on city (≈ CLOSED CITY, CITYSCAPE) and terrain (no counterpart) closed at
# 4K², 16K², 64K² up to --max-resolution, on forest (≈ VILLA, SHIP) in static mode (first and
# second surface: its trees and ground are open meshes) likewise, and on city open up to 8K², with
# the paper's sizes beside ours.
#   scripts/reproduce/scandolo2016-table1.sh [--max-resolution 256K] [sweep options]
# shellcheck source=scripts/reproduce/common.sh
source "$(dirname "$0")/common.sh"
# Cap: city open up to 8K². Open, the ground is a point interval of changing depth, so the
# hierarchy keeps about a node per texel (mh 70 MiB at 4K², ×4 per doubling; mmh peaks at
# 1.3 GiB at 4K², ~20 GiB at 16K²).
up_to_8k=$(capped 8K 4K)
sweep --schemes mh,mmh,cpvs,cpvs-fast --scenes city:full,terrain:full --modes closed \
  --resolutions "$(resolutions 4K 4)"
sweep --schemes mh,mmh,cpvs,cpvs-fast --scenes city:full --modes open --resolutions "$up_to_8k"
sweep --schemes mh,mmh,cpvs,cpvs-fast --scenes forest:full --modes static \
  --resolutions "$(resolutions 4K 4)"
tabulate
