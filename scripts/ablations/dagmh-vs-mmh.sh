#!/usr/bin/env bash
# Ablation behind issue 14's question (README "Why DAG-MH is larger than MMH here"): where the
# bytes of `mmh` and `dag-mh` go, against the `mh` both start from, on city:cityscape (the
# calibrated city), city:full and tangle:full closed at 4K², 16K², 64K². Builds mh, mmh and dag-mh at their
# defaults (one depth pass and one hierarchy per cell) and dag-mh with skip-level 0, then prints
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
common=(--scenes city:cityscape,city:full,tangle:full --modes closed --resolutions "$resolutions"
  --part-size 32K --parts "$out/parts" --out "$out/records" --no-bench)
"$sb" sweep --schemes mh,mmh,dag-mh "${common[@]}"
"$sb" sweep --schemes dag-mh -p skip-level=0 "${common[@]}"
/usr/bin/python3 scripts/ablations/dagmh_vs_mmh.py "$out/records" | tee "$out/table.md"
