#!/usr/bin/env bash
# Issue 16's build-time goal, timed in turn: `delta-dag`'s whole build beside `dag-mh`'s. Per
# cell and per pair, `shadowbench build --scheme dag-mh` then `--scheme delta-dag` (--no-bench
# --no-verify: the record's time_s.total, the depth pass, the MH and the encode step), one after
# the other, so that both see the machine alike; a pair's ratio is delta-dag's time over
# dag-mh's, and the median of the pairs is the figure (this machine's builds spread by 20 % from
# run to run, a pair's two builds less). City, terrain and tangle closed and the forest static at
# --max-resolution (default 16K here). The table goes to results/reproduce/delta-dag-build-time.txt.
#   scripts/reproduce/delta-dag-build-time.sh [--max-resolution 16K] [--pairs 5]
pairs=5
args=()
while [ $# -gt 0 ]; do
  case $1 in
    --pairs)
      [[ ${2:-} =~ ^[1-9][0-9]?$ ]] || { echo "delta-dag-build-time: --pairs needs 1 to 99" >&2; exit 2; }
      pairs=$2
      shift 2 ;;
    *) args+=("$1"); shift ;;
  esac
done
# shellcheck source=scripts/reproduce/common.sh
source "$(dirname "$0")/common.sh" --max-resolution 16K "${args[@]}"
r=$(label "$max_texels")
report=$out/$table.txt
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
: >"$report.tmp"
total_s() {
  /usr/bin/python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["time_s"]["total"])' "$1"
}
for cell in "tangle:full closed" "terrain:full closed" "city:full closed" "forest:full static"; do
  read -r scene mode <<<"$cell"
  ratios=()
  for pair in $(seq "$pairs"); do
    times=()
    for scheme in dag-mh delta-dag; do
      rm -rf "${scratch:?}"/*
      echo "shadowbench build --scheme $scheme -s $scene -m $mode -r $r --no-bench --no-verify" >>"$log"
      "$sb" build --scheme "$scheme" -s "$scene" -m "$mode" -r "$r" --no-bench --no-verify \
        --results "$scratch" >>"$log" 2>&1
      times+=("$(total_s "$(find "$scratch" -name '*.json' | head -1)")")
    done
    ratio=$(/usr/bin/python3 -c 'import sys; print(f"{float(sys.argv[2]) / float(sys.argv[1]):.2f}")' "${times[@]}")
    ratios+=("$ratio")
    printf '%s %s %s², pair %d: dag-mh %.2f s, delta-dag %.2f s: %s×\n' "$scene" "$mode" "$r" \
      "$pair" "${times[@]}" "$ratio" | tee -a "$report.tmp"
  done
  /usr/bin/python3 -c 'import statistics, sys; r = sorted(map(float, sys.argv[2:]))
print(f"{sys.argv[1]}: median {statistics.median(r):.2f}× ({r[0]:.2f}–{r[-1]:.2f})")' \
    "$scene $mode $r²" "${ratios[@]}" | tee -a "$report.tmp"
done
mv "$report.tmp" "$report"
echo "wrote $report"
