#!/usr/bin/env bash
# Issue 16's lookup goals, timed in turn: point lookups and 9×9 PCF of `delta-dag` beside
# `dag-mh`'s. Per cell both structures are built once, verified and saved (kept in
# results/reproduce/delta-dag-lookups/structures, so a stopped run resumes), then
# `shadowbench bench DAG-MH DELTA-DAG --filters 1,9 --rounds 9` runs both on the same queries in
# each round; the rounds' ratios are the figures (README, "Using the CLI"). City, terrain and
# tangle closed and the forest static, from 16K² to --max-resolution (default 64K here), and the
# city open at 16K² (a build of 7–9 GB there; at 64K² its merge would hold about four times as
# much, more than this machine's 24 GiB). With --skip-budget KIB, a third structure per cell,
# `delta-dag` built with `-p skip-budget=KIB` (a deeper skip table), runs in turn beside the two.
# The bench output goes to results/reproduce/delta-dag-lookups.txt.
#   scripts/reproduce/delta-dag-lookups.sh [--max-resolution 64K] [--skip-budget 4096]
args=()
variants=(dag-mh delta-dag)
while [ $# -gt 0 ]; do
  case $1 in
    --skip-budget)
      [[ ${2:-} =~ ^[1-9][0-9]{0,6}$ ]] || { echo "delta-dag-lookups: --skip-budget needs KiB" >&2; exit 2; }
      variants+=("delta-dag:skip-budget=$2")
      shift 2 ;;
    *) args+=("$1"); shift ;;
  esac
done
# shellcheck source=scripts/reproduce/common.sh
source "$(dirname "$0")/common.sh" --max-resolution 64K "${args[@]}"
structures=$out/$table/structures
sb_path=$(realpath "$sb")
mkdir -p "$structures"
report=$out/$table.txt
: >"$report.tmp"
for r in $(resolutions 16K 4 | tr , ' '); do
  parts=()
  (($(texels "$r") <= $(texels "$part_size"))) ||
    parts=(--part-size "$part_size" --parts "$out/parts")
  cells=("city:full closed" "terrain:full closed" "tangle:full closed" "forest:full static")
  [ "$r" != 16K ] || cells+=("city:full open")
  for cell in "${cells[@]}"; do
    read -r scene mode <<<"$cell"
    files=()
    for variant in "${variants[@]}"; do
      scheme=${variant%%:*}
      params=()
      [ "$variant" = "$scheme" ] || params=(-p "${variant#*:}")
      files+=("${scene%%:*}-$mode-$r-${variant/:/-}.sb")
      file=$structures/${files[-1]}
      [ -f "$file" ] && continue
      echo "shadowbench build --scheme $scheme ${params[*]} -s $scene -m $mode -r $r ${parts[*]} -o $file" |
        tee -a "$log"
      "$sb" build --scheme "$scheme" "${params[@]}" -s "$scene" -m "$mode" -r "$r" "${parts[@]}" \
        --no-bench --results "$out/$table/records" -o "$file" >>"$log"
    done
    echo "## $scene $mode, $r²: shadowbench bench ${files[*]} --filters 1,9 --rounds 9" |
      tee -a "$report.tmp"
    (cd "$structures" && "$sb_path" bench "${files[@]}" -s "$scene" --filters 1,9 --rounds 9) |
      tee -a "$report.tmp"
  done
done
mv "$report.tmp" "$report"
echo "wrote $report"
