#!/usr/bin/env bash
# Ablation behind delta-dag's README "Why the ratio grows with the skip table": how much walking
# a point lookup and a 9×9 kernel take. Commit 03e053d with delta-dag-kernel-counts.patch: the walks
# count, on their thread, the packs a kernel walk decodes to visit their children, the steps to a
# child (a kernel's steps to each child it overlaps included) and the skip-table entries read, and
# `shadowbench bench` prints them per query (100 000 queries of each set, one thread) before each
# timing. Per scene (city, terrain, tangle closed, forest static) delta-dag is built and saved.
#   scripts/ablations/delta-dag-kernel-counts.sh [resolution, default 16K]
# shellcheck source=scripts/ablations/patched-build.sh
source "$(dirname "$0")/patched-build.sh"
resolution=${1:-16K}
build_at counts 03e053d delta-dag-kernel-counts.patch
sb=$work/counts-build/harness/shadowbench
for build in "city:full closed" "terrain:full closed" "tangle:full closed" "forest:full static"; do
  read -r scene mode <<<"$build"
  "$sb" build --scheme delta-dag -s "$scene" -m "$mode" -r "$resolution" --no-bench \
    --no-verify --results "$work/records" -o "$work/structure.sb" >/dev/null
  echo "$scene $mode $resolution:"
  "$sb" bench "$work/structure.sb" -s "$scene" --filters 1,9 --rounds 3
done
