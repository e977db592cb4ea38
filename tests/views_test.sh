#!/usr/bin/env bash
# End-to-end through `shadowbench path` and `shadowbench views` as a user runs them: a small path
# written and scored for CSM, IASM and a saved structure, its records, pictures and tables; and
# clear errors (exit 2, one line naming the field) on a bad path, technique or parameter.
#   tests/views_test.sh path/to/shadowbench
set -euo pipefail
sb=$1
scripts=$(cd "$(dirname "$0")/../scripts" && pwd)
# shellcheck source=support/cli.sh
source "$(dirname "$0")/support/cli.sh"

"$sb" path --scene city --frames 2 -o "$work/path.json" > /dev/null
# A small frame keeps the test fast; the path is the generated one, resized.
/usr/bin/python3 - "$work/path.json" <<'PY'
import json, sys
path = json.load(open(sys.argv[1]))
path["width"], path["height"] = 96, 54
json.dump(path, open(sys.argv[1], "w"))
PY
"$sb" build --scheme mh --scene city -m closed -r 256 -o "$work/mh.sb" --results "$work/builds" --no-bench > /dev/null
"$sb" views --scene city --path "$work/path.json" --structure "$work/mh.sb" --images all \
  --out "$work/views" > "$work/views.txt"
records=("$work/views"/*.json)
[ ${#records[@]} -eq 3 ] || fail "expected 3 view records, got ${#records[@]}"
grep -q "^| csm |" "$work/views.txt" && grep -q "^| iasm |" "$work/views.txt" &&
  grep -q "^| mh 256² closed |" "$work/views.txt" || fail "summary lacks a technique: $(cat "$work/views.txt")"
for f in 000 001; do
  [ -s "$work/views/images/truth/truth-$f.png" ] && [ -s "$work/views/images/truth/truth-$f.exr" ] ||
    fail "truth picture of frame $f missing"
done
[ "$(find "$work/views/images" -name 'error-*.png' | wc -l)" -eq 6 ] || fail "error maps missing"
/usr/bin/python3 "$scripts/views_tables.py" "$work/views" > "$work/tables.md"
grep -q "Stage costs beside Alecu 2014 Table 4.1" "$work/tables.md" || fail "tables: $(cat "$work/tables.md")"
grep -q "| mh | closed | 256 |" "$work/tables.md" || fail "no CSM comparison row for mh"
/usr/bin/python3 "$scripts/plot_views.py" "$work/views" --out "$work/plots" > /dev/null
[ -s "$work/plots/error-memory_city-walk.png" ] || fail "no error-against-memory plot: $(ls "$work/plots")"

# Bad input, refused before the first frame.
bad() {  # bad NAME PYTHON-EDIT: a copy of the path edited by PYTHON-EDIT (p is the path)
  /usr/bin/python3 - "$work/path.json" "$work/$1.json" "$2" <<'PY'
import json, sys
p = json.load(open(sys.argv[1]))
exec(sys.argv[3])
open(sys.argv[2], "w").write(json.dumps(p))
PY
}
bad nan 'p["frames"][1]["eye"][2] = "NaN"'
refused "frames[1].eye" "$sb" views --scene city --path "$work/nan.json" --out "$work/x"
bad empty 'p["frames"] = []'
refused "frames" "$sb" views --scene city --path "$work/empty.json" --out "$work/x"
bad huge 'p["width"] = 100000'
refused "width" "$sb" views --scene city --path "$work/huge.json" --out "$work/x"
refused "unknown view technique 'vsm'" "$sb" views --scene city --path "$work/path.json" -t vsm
refused "lambda" "$sb" views --scene city --path "$work/path.json" -p csm:lambda=200
refused "must name one of --technique" "$sb" views --scene city --path "$work/path.json" -p lambda=20
refused "built from another scene" "$sb" views --scene terrain --structure "$work/mh.sb" --frames 1 --out "$work/x"
echo "views: all passed"
