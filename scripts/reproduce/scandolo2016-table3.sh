#!/usr/bin/env bash
# Scandolo et al. 2016 (MMH), Table 3: how `mmh` (search distance 1000) rejects the subtree pairs
# it tests — interval mismatch, offset too large, full test — as % of the pairs tested, on city
# (≈ CLOSED CITY, CITYSCAPE) closed at 16K² and 64K² up to --max-resolution, with the paper's
# percentages beside ours. Two rows each: our interval test both ways (the default, with lookup
# timings for the other tables) and Alg. 3's one-way test (interval-test=paper, --no-bench: the
# same structure, only the counters differ).
#   scripts/reproduce/scandolo2016-table3.sh [--max-resolution 256K] [sweep options]
# shellcheck source=scripts/reproduce/common.sh
source "$(dirname "$0")/common.sh"
sweep --schemes mmh --scenes city:full --modes closed \
  --resolutions "$(resolutions 16K 4)"
sweep --schemes mmh --param interval-test=paper --scenes city:full --modes closed \
  --resolutions "$(resolutions 16K 4)" --no-bench
tabulate
