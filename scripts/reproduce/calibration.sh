#!/usr/bin/env bash
# The calibrated city (README, "Calibrated stand-ins"): `cpvs` closed on city:cityscape from 4K²
# to --max-resolution against Scandolo & Eisemann 2021 Table 1's City DAG row it was fitted to,
# with `cpvs-fast`, `mh`, `mmh` and `dag-mh` on the same cells as predictions beside the papers'
# rows. Always the calibrated stand-ins: records and table in results/reproduce/calibrated/.
#   scripts/reproduce/calibration.sh [--max-resolution 64K] [sweep options]
set -- --stand-ins calibrated "$@"
# shellcheck source=scripts/reproduce/common.sh
source "$(dirname "$0")/common.sh"
sweep --schemes cpvs,cpvs-fast,mh,mmh,dag-mh --scenes city:full --modes closed \
  --resolutions "$(resolutions 4K)"
tabulate
