#!/usr/bin/env bash
# Scandolo & Eisemann 2021 (DAG-MH), Table 1: the size of `cpvs` (the paper's DAG), `mmh` (search
# distance 1000) and `dag-mh` (treelets of 4, chunks of 32) on city (≈ Citadel, City) closed from
# 4K² to --max-resolution (`dag-mh` one doubling beyond: 512K² by default, the paper's last row), on terrain (no counterpart) and tangle (≈ Hairball) closed and forest
# (≈ Trees) static (the paper's first and second surface) at 4K², 16K², 64K², and on city open
# up to 8K² (`cpvs` on tangle up to 16K²; scandolo2016-table1.sh says why), beside the
# uncompressed 32-bit map and the paper's sizes. `dag-mh` with skip level 0 (no skip list) is a
# row of its own on the closed and static builds (city up to 32K²: below level 0 a node of the
# city counts 2^24 values or more at 64K², beyond §3.4's 24-bit counts).
#   scripts/reproduce/scandolo2021-table1.sh [--max-resolution 256K] [sweep options]
# shellcheck source=scripts/reproduce/common.sh
source "$(dirname "$0")/common.sh"
up_to_16k=$(capped 16K 4K 4)
up_to_8k=$(capped 8K 4K)
sweep --schemes mmh,dag-mh,cpvs,cpvs-fast --scenes city:full --modes closed \
  --resolutions "$(resolutions 4K)"
sweep --schemes dag-mh --scenes city:full --modes closed --resolutions "$(label $((max_texels * 2)))"
sweep --schemes mmh,dag-mh,cpvs,cpvs-fast --scenes terrain:full --modes closed \
  --resolutions "$(resolutions 4K 4)"
sweep --schemes mmh,dag-mh --scenes tangle:full --modes closed \
  --resolutions "$(resolutions 4K 4)"
sweep --schemes mmh,dag-mh,cpvs,cpvs-fast --scenes city:full --modes open \
  --resolutions "$up_to_8k"
sweep --schemes mmh,dag-mh,cpvs,cpvs-fast --scenes forest:full --modes static \
  --resolutions "$(resolutions 4K 4)"
sweep --schemes cpvs,cpvs-fast --scenes tangle:full --modes closed --resolutions "$up_to_16k"
sweep --schemes dag-mh -p skip-level=0 --scenes city:full --modes closed \
  --resolutions "$(capped 32K 4K)"
sweep --schemes dag-mh -p skip-level=0 --scenes terrain:full,tangle:full --modes closed \
  --resolutions "$(resolutions 4K 4)"
sweep --schemes dag-mh -p skip-level=0 --scenes forest:full --modes static \
  --resolutions "$(resolutions 4K 4)"
tabulate
