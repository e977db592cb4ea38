#!/usr/bin/env bash
# End-to-end through the shadowbench CLI as a user runs it: build and save, query, verify,
# sweep and resume, tables from records, the registry as JSON, and clear errors (exit 2) on bad
# input, refused outputs and lost output, found before any work.
#   tests/cli_test.sh path/to/shadowbench
set -euo pipefail
sb=$1
# shellcheck source=support/cli.sh
source "$(dirname "$0")/support/cli.sh"
# A scene that does not exist: a refusal that names something else was made before the scene
# was opened, so before any work.
missing=$work/missing.obj

"$sb" build --scene city -m closed -r 64 -o "$work/city.sb" --results "$work/builds" --no-bench > "$work/build.txt"
grep -q "0 mismatches" "$work/build.txt" || fail "build did not verify: $(cat "$work/build.txt")"
ls "$work/builds"/*.json > /dev/null || fail "build wrote no record"

# Queries: a point far behind everything is shadowed where the map is covered, taps outside lit.
printf '0.5 0.5 1.0\n\n2 2 0.5 9\n0.5 0.5 0.0 3\n' | "$sb" query "$work/city.sb" > "$work/answers.txt"
[ "$(sed -n 2p "$work/answers.txt")" = "1" ] || fail "a query outside the map is not lit"
[ "$(sed -n 3p "$work/answers.txt")" = "1" ] || fail "a query at depth 0 is not lit"
[ "$(wc -l < "$work/answers.txt")" -eq 3 ] || fail "blank query lines must be skipped"
# A line is answered only if it is exactly `x y z [k]`; anything else names its line.
for bad in "0.5 0.5 0.3 9 junk" "0.5 0.5 0.3 9.7" "0.5 0.5 0.3abc"; do
  set +e
  printf '0.5 0.5 0.3\n%s\n' "$bad" | "$sb" query "$work/city.sb" > /dev/null 2> "$work/err.txt"; rc=$?
  set -e
  [ $rc -eq 2 ] && grep -q "query line 2" "$work/err.txt" || fail "query '$bad': rc $rc, $(cat "$work/err.txt")"
done

"$sb" verify "$work/city.sb" --scene city | grep -q "0 mismatches" || fail "verify of a saved structure"
# The structure remembers its scene: verifying against another names that, not mismatches.
set +e
"$sb" verify "$work/city.sb" --scene terrain > /dev/null 2> "$work/err.txt"; rc=$?
set -e
[ $rc -eq 2 ] && grep -q "built from another scene" "$work/err.txt" || fail "verify with another scene: rc $rc, $(cat "$work/err.txt")"
# The soak checks a saved structure tile by tile and resumes only a state of the same run.
"$sb" soak "$work/city.sb" --scene city --queries 1e5 --tile 32 --state "$work/soak.state" --json "$work/soak.json" | grep -q ", 0 mismatches" || fail "soak of a saved structure"
set +e
"$sb" soak "$work/city.sb" --scene city --queries 1e5 --tile 32 --seed 2 --state "$work/soak.state" > /dev/null 2> "$work/err.txt"; rc=$?
set -e
[ $rc -eq 2 ] && grep -q "seed" "$work/err.txt" || fail "soak state of another run: rc $rc, $(cat "$work/err.txt")"
# `scene info` says whether each mesh is watertight.
"$sb" scene info --scene city | grep -q "watertight" || fail "scene info reports no watertightness"

head -c 200 "$work/city.sb" > "$work/truncated.sb"
set +e
"$sb" query "$work/truncated.sb" < /dev/null 2> "$work/err.txt"; rc=$?
set -e
[ $rc -eq 2 ] && grep -q "truncated or corrupted" "$work/err.txt" || fail "truncated structure: rc $rc, $(cat "$work/err.txt")"
for bad in "build -r 3000" "build --scheme nope" "build -p nope=1" "build --scene $work/missing.obj" "build -m sideways" "build -l 5"; do
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
ls "$work/params" | grep -q "cpvs-fast_.*culling-off" || fail "sweep -p names the cell: $(ls "$work/params")"
ls "$work/params" | grep -q "_sm32_" || fail "sweep -p leaves schemes without the parameter alone"
set +e
"$sb" sweep --schemes sm32 -p culling=off --scenes city --resolutions 64 --out "$work/refused" --no-bench > /dev/null 2> "$work/err.txt"; rc=$?
set -e
[ $rc -eq 2 ] && [ ! -e "$work/refused" ] || fail "undeclared sweep parameter: rc $rc, $(cat "$work/err.txt")"

"$sb" scene export --scene forest -o "$work/forest.obj" > /dev/null
grep -q "^o open_" "$work/forest.obj" || fail "export names open meshes"

# Outputs that would destroy something, or fail only after the build, are refused before the
# scene is opened, and nothing is left behind (a FIFO stands for a device node: replacing a real
# one is what the refusal prevents, so a real one is never risked).
mkfifo "$work/fifo"
mkdir "$work/folder"
refused "refusing to replace '$work/fifo': it exists and is not a regular file" "$sb" build --scene "$missing" -o "$work/fifo"
refused "refusing to replace '$work/folder'" "$sb" build --scene "$missing" -o "$work/folder"
refused "output '$work/new/' names a folder" "$sb" build --scene "$missing" -o "$work/new/"
[ -p "$work/fifo" ] && [ -d "$work/folder" ] && [ ! -e "$work/new" ] || fail "a refused output was touched"
"$sb" scene export --scene city -o "$work/model.obj" > /dev/null
cp "$work/model.obj" "$work/model.before"
echo '{"meshes": [{"name": "model", "file": "model.obj"}]}' > "$work/scene.json"
refused "it is the input" "$sb" scene export --scene "$work/model.obj" -o "$work/./model.obj"
refused "it is the input" "$sb" build --scene "$work/model.obj" -o "$work/model.obj" -r 64 --no-bench
refused "it is the input '$work/model.obj'" "$sb" build --scene "$work/scene.json" -o "$work/../$(basename "$work")/model.obj" -r 64 --no-bench
refused "it is the input" "$sb" depth --scene "$work/scene.json" -r 64 --exr "$work/scene.json"
cmp -s "$work/model.obj" "$work/model.before" || fail "an input was overwritten by an output"
# A sweep's per-cell lock files (.locks/) are meant to stay; anything else hidden is a temporary.
leftovers=$(find "$work" -mindepth 1 -name .locks -prune -o \( -name '.*' -o -name '*.partial' \) -print)
[ -z "$leftovers" ] || fail "temporaries left behind: $leftovers"

# Everything a build is given is checked before the scene is opened; depth's EXR limit before
# the depth pass.
refused "unknown scheme 'nope'" "$sb" build --scene "$missing" --scheme nope
refused "has no parameter 'nope'" "$sb" build --scene "$missing" -p nope=1
refused "unknown depth mode 'sideways'" "$sb" build --scene "$missing" -m sideways
refused "resolution '3000'" "$sb" build --scene "$missing" -r 3000
refused "tile size 3 must be a power of two in [8, 1024]" "$sb" build --scene "$missing" --tile 3
touch "$work/plain"
refused "cannot create the folder '$work/plain/records'" "$sb" build --scene "$missing" --results "$work/plain/records"
refused "--exr is limited to 16K² maps; 32K² asked" "$sb" depth --scene "$missing" -r 32K --exr "$work/depth.exr"

# Resolutions: 1M is 1024K; fractions and zero are refused.
refused "tile size 3 must be a power of two in [8, 1048576]" "$sb" build --scene city -r 1M --tile 3
refused "tile size 3 must be a power of two in [8, 1048576]" "$sb" build --scene city -r 1m --tile 3
refused "resolution '1.5K' must be a power of two" "$sb" build --scene "$missing" -r 1.5K
refused "resolution '0' must be a power of two" "$sb" build --scene "$missing" -r 0

# A parameter given twice is refused, not its last value silently kept.
refused "parameter 'treelet-height' given twice ('3' and '4')" "$sb" build --scene "$missing" --scheme dag-mh -p treelet-height=3 -p treelet-height=4
refused "parameter 'culling' given twice" "$sb" sweep --scenes "$missing" --schemes cpvs-fast -p culling=off -p culling=on --out "$work/twice"

# Command-line errors exit 2 with one line; --help still succeeds.
refused "not expected: --bogus" "$sb" build --bogus
refused "--resolution" "$sb" build -r
refused "--light" "$sb" build --light x
"$sb" build --help | grep -q "^Usage:" || fail "build --help"

# Output that cannot be written fails the run, naming why: a full device, a closed stdout.
for command in "schemes" "schemes --json" "scene list" "table $work/sweep" "build --help"; do
  set +e
  $sb $command > /dev/full 2> "$work/err.txt"; full=$?
  $sb $command >&- 2> "$work/closed.txt"; closed=$?
  set -e
  [ $full -eq 2 ] && grep -qx "shadowbench: cannot write standard output: No space left on device" "$work/err.txt" ||
    fail "'$command > /dev/full': rc $full, $(cat "$work/err.txt")"
  [ $closed -eq 2 ] && grep -qx "shadowbench: cannot write standard output: Bad file descriptor" "$work/closed.txt" ||
    fail "'$command >&-': rc $closed, $(cat "$work/closed.txt")"
done
set +e
"$sb" schemes >&- 2>&-; closed=$?
set -e
[ $closed -eq 2 ] || fail "schemes with stdout and stderr closed: rc $closed"
set +e
echo "0.5 0.5 0.5" | "$sb" query "$work/city.sb" > /dev/full 2> "$work/err.txt"; full=$?
echo "0.5 0.5 0.5" | "$sb" query "$work/city.sb" >&- 2> "$work/closed.txt"; closed=$?
# Endless queries: only stopping at the first failed write ends this.
yes "0.5 0.5 0.5" | timeout 60 "$sb" query "$work/city.sb" > /dev/full 2> "$work/endless.txt"; endless=${PIPESTATUS[1]}
set -e
[ $full -eq 2 ] && grep -q "cannot write standard output: No space left on device" "$work/err.txt" || fail "query > /dev/full: rc $full, $(cat "$work/err.txt")"
[ $closed -eq 2 ] && grep -q "cannot write standard output: Bad file descriptor" "$work/closed.txt" || fail "query >&-: rc $closed, $(cat "$work/closed.txt")"
[ $endless -eq 2 ] && grep -qx "shadowbench: cannot write standard output: No space left on device" "$work/endless.txt" || fail "endless query > /dev/full: rc $endless, $(cat "$work/endless.txt")"

# Builds in parts: part files one job at a time, a merge that names what is missing, a build that
# resumes from them and answers as the whole build; several schemes from one depth pass.
parts=(--scene city -m closed -r 128 --tile 32 --part-size 64 --parts "$work/parts")
"$sb" part "${parts[@]}" --scheme sm32 --part 1 > /dev/null
refused "3 of 4 part files of sm32 are missing" "$sb" merge "${parts[@]}" --scheme sm32 --results "$work/builds" --no-bench
"$sb" build "${parts[@]}" --scheme sm32 -o "$work/parts.sb" --results "$work/builds" --no-bench > "$work/parts.txt"
grep -q "0 mismatches" "$work/parts.txt" || fail "build in parts did not verify: $(cat "$work/parts.txt")"
"$sb" build --scene city -m closed -r 128 --scheme sm32 -o "$work/whole.sb" --results "$work/builds" --no-bench > /dev/null
printf '0.25 0.5 0.4 1\n0.6 0.3 0.2 3\n0.5 0.5 0.9 9\n' > "$work/queries.txt"
cmp <("$sb" query "$work/parts.sb" < "$work/queries.txt") <("$sb" query "$work/whole.sb" < "$work/queries.txt") || fail "merged and whole structures answer differently"
# bench: one structure alone, or several of one map in turn, each beside the first by the
# rounds' ratios; a structure of another map or an even filter is refused.
"$sb" bench "$work/whole.sb" --scene city --filters 1 --rounds 1 > "$work/bench.txt"
[ "$(grep -c "ns/query (1 thread)" "$work/bench.txt")" -eq 2 ] || fail "bench of one structure: $(cat "$work/bench.txt")"
"$sb" bench "$work/whole.sb" "$work/parts.sb" --scene city --filters 1,3 --rounds 3 > "$work/bench.txt"
[ "$(grep -c "3 rounds of .* queries in turn" "$work/bench.txt")" -eq 4 ] &&
  [ "$(grep -c "parts.sb .*×" "$work/bench.txt")" -eq 4 ] || fail "bench in turn: $(cat "$work/bench.txt")"
refused "is of another map than" "$sb" bench "$work/whole.sb" "$work/city.sb" --scene city --rounds 1
for bad in 4 19 abc 3x; do
  refused "'$bad' is not a filter size: odd, from 1 to 17" "$sb" bench "$work/whole.sb" --scene city --filters "1,$bad"
done
refused "does not build in parts" "$sb" build "${parts[@]}" --scheme openvdb --results "$work/builds"
refused "must lie from the tile size 32 to below the resolution 128" "$sb" build --scene "$missing" -r 128 --tile 32 --part-size 128 --scheme sm32
refused "must name its scheme" "$sb" build --scene "$missing" --scheme sm32,sm-zstd -p block=64
refused "which is not among --scheme" "$sb" build --scene "$missing" --scheme sm32,sm-zstd -p mh:x=1
refused "--output saves one structure" "$sb" build --scene "$missing" --scheme sm32,sm-zstd -o "$work/two.sb"
"$sb" build --scene city -m closed -r 64 --scheme sm32,sm-zstd --results "$work/shared" --no-bench > /dev/null
[ "$(ls "$work/shared"/*.json | wc -l)" -eq 2 ] || fail "one depth pass for two schemes did not record both"
"$sb" estimate --scheme sm32,sm-zstd -m closed -r 1K | /usr/bin/python3 -c '
import json, sys
e = json.load(sys.stdin)
assert e["build_bytes"] == sum(s["build_bytes"] for s in e["schemes"].values()), e
assert e["schemes"]["sm32"] == {"build_bytes": 4 << 20} and "part_bytes" not in e, e
' || fail "estimate"
"$sb" estimate --scheme sm32 -m closed -r 1K --part-size 256 | /usr/bin/python3 -c '
import json, sys
e = json.load(sys.stdin)
assert (e["part_bytes"], e["merge_bytes"], e["build_bytes"]) == (256 << 10, 4 << 20, 4 << 20), e
' || fail "estimate in parts"

# The registry as JSON for scripts, values as strings as records hold them.
"$sb" schemes --json > "$work/schemes.json"
/usr/bin/python3 -c '
import json, sys
schemes = {s["name"]: s for s in json.load(open(sys.argv[1]))["schemes"]}
dag = schemes["dag-mh"]
assert dag["kind"] == "depth" and dag["paper"].startswith("Scandolo & Eisemann 2021"), dag
height = {p["name"]: p for p in dag["params"]}["treelet-height"]
assert height == {"name": "treelet-height", "help": height["help"], "type": "integer",
                  "default": "4", "min": 1, "max": 5, "sweep": ["2", "3", "4", "5"]}, height
culling = {p["name"]: p for p in schemes["cpvs-fast"]["params"]}["culling"]
assert culling == {"name": "culling", "help": culling["help"], "type": "choice", "default": "on",
                   "choices": ["on", "off"], "sweep": ["on", "off"]}, culling
assert schemes["sm32"]["params"] == [] and schemes["cpvs"]["kind"] == "voxel"
' "$work/schemes.json" || fail "schemes --json"

echo "1 passed, 0 failed"
