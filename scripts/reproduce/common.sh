# shellcheck shell=bash
# Sourced by the scripts of scripts/reproduce/ (not run): reads --max-resolution, --part-size and
# --stand-ins (every other argument goes to each sweep), builds shadowbench (Release, in build/ or
# $SHADOWBENCH_BUILD), and gives each script `resolutions`, `sweep` and `tabulate`. Records go to
# results/reproduce/records, the sweeps' output to results/reproduce/<table>/sweep.log
# and the table to results/reproduce/<table>.md; with --stand-ins calibrated, all three under
# results/reproduce/calibrated/.
set -euo pipefail
script=$(realpath "$0")
table=$(basename "$script" .sh)
command_line="scripts/reproduce/$table.sh${*:+ $*}"
cd "$(dirname "${BASH_SOURCE[0]}")/../.."

usage() {
  sed -n '2,/^#   scripts/s/^# \{0,1\}//p' "$script"
  echo "Options: --max-resolution R (default 256K, e.g. 4K for a quick run); --part-size P"
  echo "(default 32K: cells above it that build in parts do so, part files in"
  echo "results/reproduce/parts); --stand-ins full|calibrated (default full: the scripts' scenes;"
  echo "calibrated: city:cityscape, fitted to the 2021 paper's DAG column, for city:full, the"
  echo "records and tables in results/reproduce/calibrated); any other argument goes to every"
  echo "'shadowbench sweep' (e.g. --no-bench, --sampled-queries 1000000)."
}

# "4K" → 4096; fails on anything but digits with an optional K.
texels() {
  local digits=${1%[kK]}
  [[ $digits =~ ^[0-9]{1,7}$ ]] || return 1
  if [ "$digits" != "$1" ]; then echo $((10#$digits * 1024)); else echo $((10#$digits)); fi
}
label() { if (($1 >= 1024)); then echo "$(($1 / 1024))K"; else echo "$1"; fi; }

max_resolution=256K
part_size=32K
stand_ins=full
sweep_args=()
while [ $# -gt 0 ]; do
  case $1 in
    --max-resolution)
      [ $# -ge 2 ] || { echo "$table: --max-resolution needs a value" >&2; exit 2; }
      max_resolution=$2
      shift 2 ;;
    --max-resolution=*) max_resolution=${1#*=}; shift ;;
    --part-size)
      [ $# -ge 2 ] || { echo "$table: --part-size needs a value" >&2; exit 2; }
      part_size=$2
      shift 2 ;;
    --part-size=*) part_size=${1#*=}; shift ;;
    --stand-ins)
      [ $# -ge 2 ] || { echo "$table: --stand-ins needs a value" >&2; exit 2; }
      stand_ins=$2
      shift 2 ;;
    --stand-ins=*) stand_ins=${1#*=}; shift ;;
    -h | --help) usage; exit 0 ;;
    *) sweep_args+=("$1"); shift ;;
  esac
done
if ! max_texels=$(texels "$max_resolution") || ((max_texels < 8 || (max_texels & (max_texels - 1)) != 0)); then
  echo "$table: --max-resolution '$max_resolution' must be a power of two such as 4K or 64K" >&2
  exit 2
fi

# The comma-separated resolutions FIRST, FIRST·STEP, … up to --max-resolution (STEP 2 unless
# given); the maximum alone when FIRST is above it, so that a quick run still builds each cell.
resolutions() {
  local r step=${2:-2} list=()
  r=$(texels "$1")
  while ((r <= max_texels)); do
    list+=("$(label "$r")")
    r=$((r * step))
  done
  [ ${#list[@]} -gt 0 ] || list=("$(label "$max_texels")")
  (IFS=,; echo "${list[*]}")
}

# `resolutions` up to CAP at most: capped CAP FIRST [STEP] (a table's budget for costly cells).
capped() {
  local cap max_texels=$max_texels
  cap=$(texels "$1")
  ((cap > max_texels)) || max_texels=$cap
  resolutions "${@:2}"
}

# A sweep builds every parameter a script does not name at the registry's default, and the
# tables find the papers' rows at those defaults (`shadowbench schemes --json`), so the scripts
# name only the parameters they vary.

# The calibrated stand-ins (README, "Calibrated stand-ins") replace the scripts' scenes where a
# preset was fitted; the tables find scenes by generator, so they keep a folder of their own.
case $stand_ins in
  full) out=results/reproduce; calibrated=() ;;
  calibrated)
    out=results/reproduce/calibrated
    calibrated=(city:full city:cityscape tangle:full tangle:hairball) ;; # pairs: stand-in, preset
  *) echo "$table: --stand-ins '$stand_ins' must be full or calibrated" >&2; exit 2 ;;
esac
# One records folder for every table: a cell two tables need is built once.
records=$out/records
log=$out/$table/sweep.log
mkdir -p "$out/$table"
build_dir=${SHADOWBENCH_BUILD:-build}
scripts/install-deps.sh
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build_dir" -j "$(nproc)" --target shadowbench
sb=$build_dir/harness/shadowbench

# One `shadowbench sweep` into this table's records: finished cells are skipped, so a stopped
# script resumes. A failed or mismatched cell does not stop the script; it sets its exit status.
# Cells above the part size are built in parts; `sweep_part_size=4K sweep …` sets another for one
# sweep, and `sweep_part_size=whole sweep …` builds every cell whole.
status=0
sweep() {
  local parts=(--part-size "${sweep_part_size:-$part_size}" --parts "$out/parts")
  [ "${sweep_part_size:-}" != whole ] || parts=()
  local args=("$@") i
  if [ ${#calibrated[@]} -gt 0 ]; then
    local pair
    for ((pair = 0; pair < ${#calibrated[@]}; pair += 2)); do
      for i in "${!args[@]}"; do
        args[i]=${args[i]//${calibrated[pair]}/${calibrated[pair + 1]}}
      done
    done
    set -- "${args[@]}"
  fi
  echo "shadowbench sweep ${parts[*]:+${parts[*]} }$*${sweep_args[*]:+ ${sweep_args[*]}}" | tee -a "$log"
  local rc=0
  "$sb" sweep --out "$records" "${parts[@]}" "$@" "${sweep_args[@]}" >>"$log" || rc=$?
  [ $rc -ne 2 ] || exit 2 # refused its arguments (shadowbench said why); nothing was built
  [ $rc -eq 0 ] || status=1
  grep '^sweep:' "$log" | tail -n 1
}

# Writes results/reproduce/<table>.md from the records, prints it, and exits with the sweeps'
# status.
tabulate() {
  /usr/bin/python3 scripts/reproduce/paper_tables.py "$table" "$records" \
    --max-resolution "$max_resolution" --command "$command_line" >"$out/$table.md.tmp"
  mv "$out/$table.md.tmp" "$out/$table.md"
  cat "$out/$table.md"
  echo "wrote $out/$table.md"
  [ $status -eq 0 ] || echo "$table: some cells failed or did not verify; see $log" >&2
  exit $status
}
