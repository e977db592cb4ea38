#!/usr/bin/env bash
# Ablation behind delta-dag's README "Mirror symmetry, measured before building it": how many of
# the DAG's packs would remain if packs equal under the 8 mirrorings and transpositions of their
# square were one, and how many references to shared packs there would be. Commit 6ba2121 with
# delta-dag-mirror-count.patch: the encode step canonicalises every pack (children permuted,
# their transforms composed) and prints one SYM line per build; it is not a scheme parameter.
#   scripts/ablations/delta-dag-mirror-count.sh [resolutions, default "4K 16K"]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
repo=$(git -C "$here" rev-parse --show-toplevel)
resolutions=${1:-4K 16K}
work=$(mktemp -d)
trap 'git -C "$repo" worktree remove --force "$work/src" 2>/dev/null; rm -rf "$work"' EXIT
git -C "$repo" worktree add --detach "$work/src" 6ba2121 >/dev/null
git -C "$work/src" apply "$here/delta-dag-mirror-count.patch"
if ! { cmake -S "$work/src" -B "$work/build" -DCMAKE_BUILD_TYPE=Release &&
  cmake --build "$work/build" --target shadowbench -j"$(nproc)"; } >"$work/build.log" 2>&1; then
  tail -n 40 "$work/build.log" >&2
  exit 1
fi
for r in $resolutions; do
  for build in "city:full closed" "terrain:full closed" "tangle:full closed" "forest:full static"; do
    read -r scene mode <<<"$build"
    echo "$r $scene $("$work/build/harness/shadowbench" build --scheme delta-dag -s "$scene" \
      -m "$mode" -r "$r" --no-bench --no-verify --results "$work/records" 2>&1 | grep SYM)"
  done
done
