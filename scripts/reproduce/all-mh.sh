#!/usr/bin/env bash
# Every MH-family table in turn (Scandolo 2016 Tables 1–3 and Fig. 8, Scandolo & Eisemann 2021
# Tables 1–4, lookup cost), each into results/reproduce/<table>.md; the arguments go to each
# script (e.g. --max-resolution 4K). The tables with lookup timings run first, so that a cell the
# parameter sweeps share with them (built there with --no-bench) already has its timings. A
# table that fails does not stop the others; the exit status says whether any failed.
#   scripts/reproduce/all-mh.sh [--max-resolution 256K] [sweep options]
set -euo pipefail
cd "$(dirname "$0")"
failed=()
for table in scandolo2016-table1 scandolo2021-table1 scandolo2016-table2 scandolo2021-table2 \
  scandolo2016-table3 mh-lookup scandolo2016-fig8 scandolo2021-table3 scandolo2021-table4; do
  ./$table.sh "$@" || failed+=("$table")
done
[ ${#failed[@]} -eq 0 ] || { echo "all-mh: failed: ${failed[*]}" >&2; exit 1; }
echo "all-mh: wrote results/reproduce/*.md"
