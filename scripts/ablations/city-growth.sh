#!/usr/bin/env bash
# Evidence behind the calibrated city (README, "Calibrated stand-ins"): how `cpvs` closed grows
# from 4K² to 16K² on box cities of every size, with buildings turned, on hills, and on the
# preset city:cityscape. The papers' DAG grows about 2.05× per doubling on their City; a knob
# that cannot raise our growth towards it cannot calibrate the city.
#   scripts/ablations/city-growth.sh [records folder]
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:-results/ablations/city-growth}
build_dir=${SHADOWBENCH_BUILD:-build}
scripts/install-deps.sh
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build_dir" -j "$(nproc)" --target shadowbench
specs=(city:size=1 city:size=2 city:size=8 city:full city:size=2,turn=90 city:size=2,relief=400
  city:size=1,relief=400 city:size=1,relief=400,turn=90 city:cityscape)
for spec in "${specs[@]}"; do
  for r in 4K 16K; do
    dir="$out/${spec//[:=,]/_}"
    ls "$dir"/*_"$(( ${r%K} * 1024 ))"_*.json >/dev/null 2>&1 && continue
    "$build_dir/harness/shadowbench" build --scheme cpvs -s "$spec" -m closed -r "$r" --no-bench \
      --results "$dir" >/dev/null
  done
done
/usr/bin/python3 - "$out" "${specs[@]}" <<'PY'
import json, pathlib, sys
out, specs = pathlib.Path(sys.argv[1]), sys.argv[2:]
print("| scene | cpvs 4K² (MiB) | cpvs 16K² (MiB) | growth per doubling |")
print("|---|---:|---:|---:|")
for spec in specs:
    folder = out / spec.replace(":", "_").replace("=", "_").replace(",", "_")
    sizes = {}
    for path in folder.glob("*.json"):
        record = json.loads(path.read_text())
        sizes[record["resolution"]] = record["size_bytes"]["total"] / 2**20
        name = record["scene"]["name"]
    a, b = sizes[4096], sizes[16384]
    print(f"| `{spec}` ({name}) | {a:.3g} | {b:.3g} | {(b / a) ** 0.5:.3g} |")
PY
