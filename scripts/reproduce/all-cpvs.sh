#!/usr/bin/env bash
# Every CPVS table in turn (Sintorn 2014 Fig. 9, Kämpe 2015 Tables 1–4, lookup cost, Fig. 3), each into
# results/reproduce/<table>.md; the arguments go to each script (e.g. --max-resolution 4K). A
# table that fails does not stop the others; the exit status says whether any failed.
#   scripts/reproduce/all-cpvs.sh [--max-resolution 256K] [sweep options]
set -euo pipefail
cd "$(dirname "$0")"
failed=()
for table in sintorn2014-fig9 kampe2015-table1 kampe2015-table2 kampe2015-table3 \
  kampe2015-table4 cpvs-lookup kampe2015-fig3; do
  ./$table.sh "$@" || failed+=("$table")
done
[ ${#failed[@]} -eq 0 ] || { echo "all-cpvs: failed: ${failed[*]}" >&2; exit 1; }
echo "all-cpvs: wrote results/reproduce/*.md"
