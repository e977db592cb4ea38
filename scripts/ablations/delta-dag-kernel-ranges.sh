#!/usr/bin/env bash
# Ablation behind delta-dag's README "Key ranges for kernels": what key ranges settle, and what
# finer ones would. Commit cdd3b1f with delta-dag-kernel-ranges.patch: with SB_RANGE_PROBE set,
# `shadowbench bench` prints, before each timing, per kernel of 100 000 queries of each set
# (one thread): the share whose texels all give one answer (each texel's point walk), the parts
# the key-range table settled, the steps of the kernel walk, and the steps of a walk that stops at
# every node whose exact key range settles z (every pack's offsets found at load); and per point
# lookup its steps. SB_KEY_RANGE_LEVEL L puts the table L levels below the skip table's (default
# -1: one above); each level is timed, 3 rounds. Per scene (city, terrain, tangle closed, forest
# static) delta-dag is built and saved.
#   scripts/ablations/delta-dag-kernel-ranges.sh [resolution, default 16K]
# shellcheck source=scripts/ablations/patched-build.sh
source "$(dirname "$0")/patched-build.sh"
resolution=${1:-16K}
build_at ranges cdd3b1f delta-dag-kernel-ranges.patch
sb=$work/ranges-build/harness/shadowbench
for build in "city:full closed" "terrain:full closed" "tangle:full closed" "forest:full static"; do
  read -r scene mode <<<"$build"
  "$sb" build --scheme delta-dag -s "$scene" -m "$mode" -r "$resolution" --no-bench \
    --no-verify --results "$work/records" -o "$work/structure.sb" >/dev/null
  echo "$scene $mode $resolution:"
  SB_RANGE_PROBE=1 "$sb" bench "$work/structure.sb" -s "$scene" --filters 1,9 --rounds 1 |
    grep COUNTS
  for level in -2 -1 0 1 2; do
    echo "key ranges $level levels below the skip table's:"
    SB_KEY_RANGE_LEVEL=$level "$sb" bench "$work/structure.sb" -s "$scene" --filters 1,9 \
      --rounds 3 | grep -v COUNTS
  done
done
