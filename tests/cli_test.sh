#!/usr/bin/env bash
# End-to-end through the shadowbench CLI as a user runs it: build and save, query, verify,
# sweep and resume, tables from records, and clear errors (exit 2) on bad input.
#   tests/cli_test.sh path/to/shadowbench
set -euo pipefail
sb=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export SHADOWBENCH_QUIET=1
fail() { echo "FAIL: $*" >&2; exit 1; }

"$sb" build --scene city -m closed -r 64 -o "$work/city.sb" --results "$work/builds" --no-bench > "$work/build.txt"
grep -q "0 mismatches" "$work/build.txt" || fail "build did not verify: $(cat "$work/build.txt")"
ls "$work/builds"/*.json > /dev/null || fail "build wrote no record"

# Queries: a point far behind everything is shadowed where the map is covered, taps outside lit.
printf '0.5 0.5 1.0\n\n2 2 0.5 9\n0.5 0.5 0.0 3\n' | "$sb" query "$work/city.sb" > "$work/answers.txt"
[ "$(sed -n 2p "$work/answers.txt")" = "1" ] || fail "a query outside the map is not lit"
[ "$(sed -n 3p "$work/answers.txt")" = "1" ] || fail "a query at depth 0 is not lit"
[ "$(wc -l < "$work/answers.txt")" -eq 3 ] || fail "blank query lines must be skipped"

"$sb" verify "$work/city.sb" --scene city | grep -q "0 mismatches" || fail "verify of a saved structure"

head -c 200 "$work/city.sb" > "$work/truncated.sb"
set +e
"$sb" query "$work/truncated.sb" < /dev/null 2> "$work/err.txt"; rc=$?
set -e
[ $rc -eq 2 ] && grep -q "truncated or corrupted" "$work/err.txt" || fail "truncated structure: rc $rc, $(cat "$work/err.txt")"
for bad in "build -r 3000" "build --scheme nope" "build -p nope=1" "build --scene $work/missing.obj" "build -m sideways"; do
  set +e
  "$sb" $bad --no-bench > /dev/null 2> "$work/err.txt"; rc=$?
  set -e
  [ $rc -eq 2 ] && [ "$(wc -l < "$work/err.txt")" -eq 1 ] || fail "'$bad': rc $rc, $(cat "$work/err.txt")"
done

"$sb" sweep --schemes sm32 --scenes city --resolutions 64,128 --out "$work/sweep" --no-bench > "$work/sweep1.txt"
grep -q "2 cells built, 0 already done" "$work/sweep1.txt" || fail "first sweep: $(tail -1 "$work/sweep1.txt")"
rm "$(ls "$work/sweep"/*_128_*.json)"
echo '{"format": "shadowbench-record/1", "compl' > "$work/sweep/partial.json"
"$sb" sweep --schemes sm32 --scenes city --resolutions 64,128 --out "$work/sweep" --no-bench > "$work/sweep2.txt"
grep -q "1 cells built, 1 already done" "$work/sweep2.txt" || fail "resumed sweep: $(grep sweep: "$work/sweep2.txt")"
"$sb" table "$work/sweep" | grep -q "| sm32 |" || fail "table from records"
[ -f "$work/sweep/tables/tables.md" ] || fail "tables.md not written"

# A sweep parameter goes to the schemes that declare it and names the cell; an unknown one is
# refused before anything is built.
"$sb" sweep --schemes sm32,cpvs-fast -p culling=off --scenes city --resolutions 64 --out "$work/params" --no-bench > /dev/null
ls "$work/params" | grep -q "cpvs-fast_culling-off" || fail "sweep -p names the cell: $(ls "$work/params")"
ls "$work/params" | grep -q "_sm32_" || fail "sweep -p leaves schemes without the parameter alone"
set +e
"$sb" sweep --schemes sm32 -p culling=off --scenes city --resolutions 64 --out "$work/refused" --no-bench > /dev/null 2> "$work/err.txt"; rc=$?
set -e
[ $rc -eq 2 ] && [ ! -e "$work/refused" ] || fail "undeclared sweep parameter: rc $rc, $(cat "$work/err.txt")"

"$sb" scene export --scene forest -o "$work/forest.obj" > /dev/null
grep -q "^o open_" "$work/forest.obj" || fail "export names open meshes"
echo "1 passed, 0 failed"
