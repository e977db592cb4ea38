#!/usr/bin/env bash
# Ablation behind mmh's merge of parts (README "Builds in parts", schemes/mmh/README.md): what
# `mmh` would lose if a merge of parts matched each part alone. Builds `mmh` whole on city and
# terrain closed and forest static at 16K² and 64K², matching over the whole map and inside
# squares of R/4 (the 16 parts of parts-cost.sh), and prints size and merges of both. The
# confined matcher is commit a0d5eac with mmh-match-square.patch: the matcher skips pairs of packs
# in different squares, whose side SB_MMH_MATCH_SQUARE gives. It is not a scheme parameter, so
# that the registry's cells (and their records) stay as they are.
#   scripts/ablations/mmh-part-matching.sh [--max-resolution 16K] [records folder]
# shellcheck source=scripts/ablations/patched-build.sh
source "$(dirname "$0")/patched-build.sh"
resolutions="16K 64K"
if [[ ${1:-} == --max-resolution ]]; then
  [[ $2 == 16K ]] && resolutions=16K
  shift 2
fi
out=$(realpath -m "${1:-results/ablations/mmh-part-matching}")
build_at mmh-match-square a0d5eac mmh-match-square.patch
sb=$work/mmh-match-square-build/harness/shadowbench
for r in $resolutions; do
  for build in "city:full closed" "terrain:full closed" "forest:full static"; do
    read -r scene mode <<<"$build"
    "$sb" build --scheme mmh -s "$scene" -m "$mode" -r "$r" --no-bench --results "$out/whole-map"
    SB_MMH_MATCH_SQUARE=$((${r%K} * 256)) "$sb" build --scheme mmh -s "$scene" -m "$mode" \
      -r "$r" --no-bench --results "$out/squares"
  done
done
python3 - "$out" <<'PY'
import json, pathlib, sys
out = pathlib.Path(sys.argv[1])
cells = {}
for variant in ("whole-map", "squares"):
    for path in sorted((out / variant).glob("*.json")):
        record = json.loads(path.read_text())
        cell = (record["scene"]["name"], record["mode"], record["resolution"])
        cells.setdefault(cell, {})[variant] = record
print("| scene | mode | R | whole map (B) | merges | squares of R/4 (B) | merges | difference |")
print("|---|---|---:|---:|---:|---:|---:|---:|")
for (scene, mode, r), by in sorted(cells.items(), key=lambda c: (c[0][2], c[0][0])):
    if len(by) < 2:
        continue
    whole, squares = (by[v]["size_bytes"]["total"] for v in ("whole-map", "squares"))
    merges = [by[v]["counters"]["merges"] for v in ("whole-map", "squares")]
    print(f"| {scene} | {mode} | {r // 1024}K² | {whole:,} | {merges[0]:,} | {squares:,} | "
          f"{merges[1]:,} | {100 * (squares / whole - 1):+.2f}% |")
PY
