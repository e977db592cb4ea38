#!/usr/bin/env bash
# Ablation behind issue 14's question (README "Why DAG-MH is larger than MMH here"): where the
# bytes of `mmh` and `dag-mh` go, against the `mh` both start from, on city:cityscape (the
# calibrated city), city:full, terrain:full and tangle:full closed and forest:full static at 4K²,
# 16K², 64K². Builds mh, mmh and dag-mh at their
# defaults (one depth pass and one hierarchy per cell), dag-mh with skip-level 0 and, on the
# calibrated city and the tangle, mmh with the paper's float differences, then prints
# MH nodes and values, MMH merges and nodes removed, DAG-MH topology and value bytes, value bits
# per MH value, the skip list's share and each structure's bytes per MH node.
#   scripts/ablations/dagmh-vs-mmh.sh [--max-resolution 64K] [records folder]
set -euo pipefail
cd "$(dirname "$0")/../.."
resolutions=4K,16K,64K
case ${1:-} in
  --max-resolution) [ "$2" = 16K ] && resolutions=4K,16K; [ "$2" = 4K ] && resolutions=4K; shift 2 ;;
esac
out=${1:-results/ablations/dagmh-vs-mmh}
build_dir=${SHADOWBENCH_BUILD:-build}
scripts/install-deps.sh
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build_dir" -j "$(nproc)" --target shadowbench
sb=$build_dir/harness/shadowbench
common=(--resolutions "$resolutions" --part-size 32K --parts "$out/parts" --out "$out/records"
  --no-bench)
status=0
for scenes in "city:cityscape,city:full,terrain:full,tangle:full closed" "forest:full static"; do
  read -r scene_list mode <<<"$scenes"
  "$sb" sweep --schemes mh,mmh,dag-mh --scenes "$scene_list" --modes "$mode" "${common[@]}" ||
    status=1
  # Skip level 0 is refused where a node below it would count 2^24 values (city:full at 64K²).
  "$sb" sweep --schemes dag-mh -p skip-level=0 --scenes "$scene_list" --modes "$mode" \
    "${common[@]}" || status=1
done
# The paper's relative values (Scandolo 2016 §3) on the two scenes where its ranking holds.
"$sb" sweep --schemes mmh -p relative-values=float-differences \
  --scenes city:cityscape,tangle:full --modes closed "${common[@]}" || status=1
/usr/bin/python3 scripts/ablations/dagmh_vs_mmh.py "$out/records" | tee "$out/table.md"
exit $status
