#!/bin/sh
# Real records, written by the shadowbench binary for tiny cells, validated against
# harness/record.schema.json with Debian's python3-jsonschema; and records with impossible values
# refused by it, so that the check can fail (issue 11 B2).
# Usage: record_schema_test.sh SHADOWBENCH SCHEMA
set -eu
shadowbench=$1
schema=$2
python=${SB_PYTHON:-/usr/bin/python3}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export SHADOWBENCH_QUIET=1

"$python" -c 'import jsonschema' 2>/dev/null || {
  echo "record_schema_test: $python has no jsonschema module (apt-get install python3-jsonschema)" >&2
  exit 1
}
"$shadowbench" sweep --scenes city --schemes sm32,mmh --resolutions 64 --no-bench \
  --out "$work/sweep" >/dev/null
"$shadowbench" build --scene city --scheme sm32 --resolution 64 --results "$work/build" >/dev/null

"$python" - "$schema" "$work" <<'PY'
import copy, glob, json, sys
import jsonschema

schema = json.load(open(sys.argv[1]))
jsonschema.Draft202012Validator.check_schema(schema)
validator = jsonschema.Draft202012Validator(schema)
paths = sorted(glob.glob(sys.argv[2] + "/sweep/*.json") + glob.glob(sys.argv[2] + "/build/*.json"))
if len(paths) != 3:
    sys.exit(f"expected 3 records, found {paths}")
failed = False
for path in paths:
    record = json.load(open(path))
    for error in validator.iter_errors(record):
        print(f"{path}: {'.'.join(map(str, error.absolute_path))}: {error.message}")
        failed = True
    if "lookup" in record and not record["lookup"]:
        sys.exit(f"{path}: an empty lookup list")
built = json.load(open(glob.glob(sys.argv[2] + "/build/*.json")[0]))
if "lookup" not in built or "verification" not in built:
    sys.exit("the build record has no lookup timings or verification")
for field, value in [(("size_bytes", "total"), -1), (("resolution",), 100),
                     (("time_s", "total"), -0.5), (("mode",), "shut"), (("complete",), False)]:
    bad = copy.deepcopy(built)
    target = bad
    for key in field[:-1]:
        target = target[key]
    target[field[-1]] = value
    if validator.is_valid(bad):
        print(f"the schema accepts {'.'.join(field)} = {value!r}")
        failed = True
sys.exit(1 if failed else 0)
PY
echo "record_schema_test: 3 records valid"
