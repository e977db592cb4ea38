#!/usr/bin/env bash
# Shadows as a viewer sees them (issue 15), in one command: builds every registered scheme's
# structure for the scene at each resolution (saved under results/views/structures, reused when
# present), then scores CSM, IASM and every structure on the scene's camera path against ray-traced
# ground truth, writes the records and pictures, the error-against-memory plot with its Pareto
# front, and the tables (scripts/views_tables.py), all under results/views/<scene>.
#   scripts/views.sh [--scene city:full] [--path scenes/paths/city-full.json] [--mode closed]
#                    [--resolutions 1K,4K,16K] [--schemes all] [--frames N] [--out results/views]
#                    [--variants]
# --variants also runs the CSM and IASM variants of README's tables (other resolutions, cascades
# and resolution sets, IASM ranked by each frame's own importance) into the same folder.
# Any other argument goes to `shadowbench views` (e.g. -p iasm:m=8, --images all, --filter 9).
set -euo pipefail
cd "$(dirname "$0")/.."

scene=city:full
path=""
mode=""
resolutions=1K,4K,16K
schemes=all
frames=""
out=results/views
views_args=()
variants=""
while [ $# -gt 0 ]; do
  case $1 in
    --variants) variants=1; shift ;;
    --scene | --path | --mode | --resolutions | --schemes | --frames | --out)
      [ $# -ge 2 ] || { echo "views.sh: $1 needs a value" >&2; exit 2; }
      declare "${1#--}=$2"
      shift 2 ;;
    -h | --help) sed -n '2,12s/^# \{0,1\}//p' "$0"; exit 0 ;;
    *) views_args+=("$1"); shift ;;
  esac
done
generator=${scene%%:*}
# The committed path of a generator at full size; any other scene gets its generated fly-through.
[ -z "$path" ] && [ "$scene" = "$generator:full" ] && [ -f "scenes/paths/$generator-full.json" ] &&
  path="scenes/paths/$generator-full.json"
# Open geometry (the forest) has no closed interior to exploit; the others are closed solids.
[ -z "$mode" ] && { [ "$generator" = forest ] && mode=open || mode=closed; }

scripts/install-deps.sh
cmake -S . -B "${SHADOWBENCH_BUILD:-build}" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "${SHADOWBENCH_BUILD:-build}" -j "$(nproc)" --target shadowbench
sb="${SHADOWBENCH_BUILD:-build}/harness/shadowbench"

if [ "$schemes" = all ]; then
  schemes=$("$sb" schemes --json | /usr/bin/python3 -c 'import json,sys; print(",".join(s["name"] for s in json.load(sys.stdin)["schemes"]))')
fi
structures=()
slug=${scene//[^A-Za-z0-9]/-}
for r in ${resolutions//,/ }; do
  for s in ${schemes//,/ }; do
    file="$out/structures/$slug/$s-$mode-$r.sb"
    if [ ! -f "$file" ]; then
      mkdir -p "$(dirname "$file")"
      "$sb" build --scheme "$s" --scene "$scene" -m "$mode" -r "$r" -o "$file" --no-bench \
        --results "$out/structures/$slug/records" || { echo "views.sh: $s at $r failed; left out" >&2; continue; }
    fi
    structures+=("$file")
  done
done

path_args=()
[ -n "$path" ] && path_args=(--path "$path")
[ -n "$frames" ] && path_args+=(--frames "$frames")
views="$out/$slug"
"$sb" views --scene "$scene" "${path_args[@]}" \
  ${structures[@]:+--structure "$(IFS=,; echo "${structures[*]}")"} --out "$views" "${views_args[@]}"
if [ -n "$variants" ]; then
  for variant in "-t iasm -p iasm:importance=same-frame" "-t iasm -p iasm:resolution-set=even-256" \
                 "-t csm -p csm:resolution=512" "-t csm -p csm:resolution=2048" "-t csm -p csm:cascades=4"; do
    # shellcheck disable=SC2086
    "$sb" views --scene "$scene" "${path_args[@]}" $variant --images none --out "$views" "${views_args[@]}"
  done
fi
/usr/bin/python3 scripts/plot_views.py "$views" --out "$views/plots"
/usr/bin/python3 scripts/views_tables.py "$views" | tee "$views/tables.md"
