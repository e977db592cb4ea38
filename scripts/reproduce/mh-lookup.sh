#!/usr/bin/env bash
# Lookup cost of the MH family (Scandolo 2016 §4, Scandolo & Eisemann 2021 §4.2): ns per query of
# `mh`, `mmh` and `dag-mh` at 1×1, 3×3 and 5×5 and the ratios to 1×1, uniform and view queries,
# and mmh/mh and dag-mh/mmh, on city (≈ CLOSED CITY, Citadel) closed at 4K², 16K², 64K² up to
# --max-resolution and on every other scene and resolution the records folder holds (the
# Table 1 scripts build them); `cpvs` and `sm32` beside them where built.
#   scripts/reproduce/mh-lookup.sh [--max-resolution 256K] [sweep options]
# shellcheck source=scripts/reproduce/common.sh
source "$(dirname "$0")/common.sh"
sweep --schemes mh,mmh,dag-mh --scenes city:full --modes closed --resolutions "$(resolutions 4K 4)"
tabulate
