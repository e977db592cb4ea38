#!/usr/bin/env bash
# The calibrated stand-ins (README, "Calibrated stand-ins"): `cpvs` closed on city:cityscape and
# tangle:hairball from 4K² to --max-resolution against the Scandolo & Eisemann 2021 Table 1 DAG
# rows they were fitted to (City, Hairball), with `cpvs-fast`, `mh`, `mmh` and `dag-mh` on the
# same cells as predictions beside the papers' rows. Always the calibrated stand-ins: records and table in results/reproduce/calibrated/.
#   scripts/reproduce/calibration.sh [--max-resolution 64K] [sweep options]
set -- --stand-ins calibrated "$@"
# shellcheck source=scripts/reproduce/common.sh
source "$(dirname "$0")/common.sh"
sweep --schemes cpvs,cpvs-fast,mh,mmh,dag-mh --scenes city:full,tangle:full --modes closed \
  --resolutions "$(resolutions 4K)"
tabulate
