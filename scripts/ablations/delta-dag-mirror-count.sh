#!/usr/bin/env bash
# Ablation behind delta-dag's README "Mirror symmetry, measured before building it": how many of
# the DAG's packs would remain if packs equal under the 8 mirrorings and transpositions of their
# square were one, and how many references to shared packs there would be. Commit 6ba2121 with
# delta-dag-mirror-count.patch: the encode step canonicalises every pack (children permuted,
# their transforms composed) and prints one SYM line per build; it is not a scheme parameter.
#   scripts/ablations/delta-dag-mirror-count.sh [resolutions, default "4K 16K"]
# shellcheck source=scripts/ablations/patched-build.sh
source "$(dirname "$0")/patched-build.sh"
resolutions=${1:-4K 16K}
build_at mirror-count 6ba2121 delta-dag-mirror-count.patch
sb=$work/mirror-count-build/harness/shadowbench
for r in $resolutions; do
  for build in "city:full closed" "terrain:full closed" "tangle:full closed" "forest:full static"; do
    read -r scene mode <<<"$build"
    echo "$r $scene $("$sb" build --scheme delta-dag -s "$scene" -m "$mode" -r "$r" --no-bench \
      --no-verify --results "$work/records" 2>&1 | grep SYM)"
  done
done
