#!/usr/bin/env bash
# The Snakemake workflow (scripts/workflow/) at the CI size: runs scripts/workflow/config/ci.yaml
# in a temporary folder, then builds each of its scheme cells whole and requires that the merged
# structure answers exactly as the whole build on the same queries (every texel centre on the part
# borders, random points and 3×3 PCF elsewhere, several depths each), that each merge left a record
# naming its part size and that a second run has nothing to do.
#   tests/workflow_test.sh [--profile DIR] path/to/shadowbench
# Locally with --cores 2 by default; --profile runs it through that Snakemake profile instead
# (scripts/slurm/one-node.sh passes scripts/workflow/profiles/slurm). SHADOWBENCH_WORKFLOW_DIR
# keeps the run's folder (default: a temporary one, removed unless the test fails);
# SHADOWBENCH_WORKFLOW_CONFIG runs another config (default scripts/workflow/config/ci.yaml).
set -euo pipefail
fail() { echo "FAIL: workflow_test: $*" >&2; exit 1; }

profile=()
if [ "${1:-}" = "--profile" ]; then
  [ $# -ge 2 ] || fail "--profile needs a folder"
  profile=(--profile "$(realpath "$2")")
  shift 2
fi
[ $# -eq 1 ] || fail "usage: tests/workflow_test.sh [--profile DIR] path/to/shadowbench"
sb=$(realpath "$1")
[ -x "$sb" ] || fail "'$1' is not an executable shadowbench"
repository=$(realpath "$(dirname "$0")/..")
snakefile=$repository/scripts/workflow/Snakefile
config=$(realpath "${SHADOWBENCH_WORKFLOW_CONFIG:-$repository/scripts/workflow/config/ci.yaml}")
command -v snakemake > /dev/null ||
  fail "snakemake is not installed: apt-get install -y snakemake (scripts/install-deps.sh)"

if [ -n "${SHADOWBENCH_WORKFLOW_DIR:-}" ]; then
  work=$SHADOWBENCH_WORKFLOW_DIR
  mkdir -p "$work"
else
  work=$(mktemp -d)
  # Kept when the test fails: the logs it names are in it.
  trap 'if [ $? -eq 0 ]; then rm -rf "$work"; else echo "workflow_test: kept $work" >&2; fi' EXIT
fi
work=$(realpath "$work")
results=$work/results
export SHADOWBENCH_QUIET=1

snakemake_run() {
  local cores=()
  [ ${#profile[@]} -gt 0 ] || cores=(--cores 2)
  snakemake -s "$snakefile" --configfile "$config" --directory "$work" \
    --config shadowbench="$sb" results="$results" "${cores[@]}" "${profile[@]}" "$@"
}

snakemake_run > "$work/snakemake.log" 2>&1 || {
  tail -n 40 "$work/snakemake.log" >&2
  for log in "$results"/logs/*/*/*.log; do [ -f "$log" ] && { echo "== $log" >&2; tail -n 5 "$log" >&2; }; done
  fail "the workflow failed (log: $work/snakemake.log)"
}
[ -s "$results/tables/tables.md" ] || fail "the workflow wrote no $results/tables/tables.md"

# A second run finds every output up to date.
snakemake_run --dry-run > "$work/again.log" 2>&1 || fail "dry run after the workflow: $(tail -n 5 "$work/again.log")"
grep -q "Nothing to be done" "$work/again.log" ||
  fail "a second run would redo jobs: $(grep -A8 '^Job stats' "$work/again.log")"

# Queries (x y z [k] per line) for a map of side R cut into parts of side P: every texel centre of
# the texel rows and columns on either side of each part border at three depths, and 20000 random
# points, half of them 3×3 PCF, at random depths. Seeded: the same queries every run.
write_queries() {
  /usr/bin/python3 - "$1" "$2" <<'EOF'
import random, sys
resolution, part = int(sys.argv[1]), int(sys.argv[2])
borders = [b + d for b in range(part, resolution, part) for d in (-1, 0)]
out = sys.stdout
for line in borders:
    for t in range(resolution):
        for z in (0.25, 0.5, 0.75):
            out.write(f"{(line + 0.5) / resolution} {(t + 0.5) / resolution} {z}\n")
            out.write(f"{(t + 0.5) / resolution} {(line + 0.5) / resolution} {z}\n")
rng = random.Random(12)
for i in range(20000):
    k = " 3" if i % 2 else ""
    out.write(f"{rng.random()} {rng.random()} {rng.random()}{k}\n")
EOF
}

cells=0
while IFS=$'\t' read -r -a cell; do
  cell_set=${cell[0]} scheme=${cell[1]} resolution=${cell[2]} part_size=${cell[3]}
  build=("${cell[@]:4}")
  merged=$results/structures/$cell_set/$scheme.sb
  [ -s "$merged" ] || fail "$cell_set/$scheme: the merge wrote no structure $merged"
  whole=$work/whole/$cell_set-$scheme.sb
  mkdir -p "$work/whole"
  "$sb" "${build[@]}" -o "$whole" --results "$work/whole/records" --no-bench > "$work/whole/$cell_set-$scheme.txt" 2>&1 ||
    fail "$cell_set/$scheme: whole build '${build[*]}' failed: $(tail -n 3 "$work/whole/$cell_set-$scheme.txt")"

  write_queries "$resolution" "$part_size" > "$work/queries.txt"
  "$sb" query "$merged" < "$work/queries.txt" > "$work/merged.answers" || fail "$cell_set/$scheme: query of the merged structure failed"
  "$sb" query "$whole" < "$work/queries.txt" > "$work/whole.answers" || fail "$cell_set/$scheme: query of the whole build failed"
  queries=$(wc -l < "$work/queries.txt")
  [ "$(wc -l < "$work/merged.answers")" -eq "$queries" ] || fail "$cell_set/$scheme: $queries queries, $(wc -l < "$work/merged.answers") answers"
  if ! cmp -s "$work/merged.answers" "$work/whole.answers"; then
    first=$(awk 'NR == FNR { merged[NR] = $0; next } merged[FNR] != $0 { print FNR; exit }' \
              "$work/merged.answers" "$work/whole.answers")
    fail "$cell_set/$scheme: the merged structure answers unlike the whole build, first at query $first '$(sed -n "${first}p" "$work/queries.txt")': merged $(sed -n "${first}p" "$work/merged.answers"), whole $(sed -n "${first}p" "$work/whole.answers")"
  fi
  if ! grep -qv '^0$' "$work/whole.answers" || ! grep -qv '^1$' "$work/whole.answers"; then
    fail "$cell_set/$scheme: every answer is the same, so the queries test nothing"
  fi

  # The merge's record: this cell, complete, with its part size.
  /usr/bin/python3 - "$results/records" "$scheme" "$resolution" "$part_size" <<'EOF' || fail "$cell_set/$scheme: no record of the merge names part size $part_size (records: $results/records)"
import json, pathlib, sys
folder, scheme, resolution, part_size = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
records = [json.loads(path.read_text()) for path in pathlib.Path(folder).glob("*.json")]
sys.exit(0 if any(record.get("complete") and record["scheme"]["name"] == scheme and
                  record["resolution"] == resolution and record.get("part_size") == part_size
                  for record in records) else 1)
EOF
  echo "workflow_test: $cell_set/$scheme: merged answers $queries queries as the whole build" \
    "(files: merged $(stat -c %s "$merged") bytes, whole $(stat -c %s "$whole"))"
  cells=$((cells + 1))
done < <(/usr/bin/python3 "$repository/scripts/workflow/cell_sets.py" "$config" whole-builds)
[ "$cells" -gt 0 ] || fail "$config names no scheme cell"

# A config that cannot describe a sweep is refused before any job, naming the key.
sed 's/part_size: .*/part_size: 3K/' "$config" > "$work/bad.yaml"
if snakemake -s "$snakefile" --configfile "$work/bad.yaml" --directory "$work" \
     --config shadowbench="$sb" results="$work/bad" --cores 1 --dry-run > "$work/bad.log" 2>&1; then
  fail "a part size of 3K was accepted"
fi
grep -q "part_size: '3K' is not a power of two" "$work/bad.log" || fail "bad part size: $(cat "$work/bad.log")"
echo "workflow_test: $cells cells, merged structures answer as whole builds"
