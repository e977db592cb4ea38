#!/usr/bin/env bash
# Scandolo & Eisemann 2021 (DAG-MH), Table 2: the build time of `cpvs` (the paper's DAG), `mh`,
# `mmh` and `dag-mh`, total and without the depth map, and the depth map's share, on city
# (≈ Citadel) closed at 4K², 16K², 64K² up to --max-resolution, with the paper's times beside ours.
#   scripts/reproduce/scandolo2021-table2.sh [--max-resolution 256K] [sweep options]
# shellcheck source=scripts/reproduce/common.sh
source "$(dirname "$0")/common.sh"
sweep --schemes cpvs,cpvs-fast,mh,mmh,dag-mh --scenes city:full --modes closed --resolutions "$(resolutions 4K 4)"
tabulate
