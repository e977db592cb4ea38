#!/usr/bin/env bash
# Ablation behind delta-dag's README "Topology-only sharing and value prediction, measured before
# building them": what predicting a pack's values inside the pack would save. Commit 615258a with
# delta-dag-value-prediction.patch: after the layout, the encode step codes each pack's values as
# stored (one width and one shift for all), as the first value and the others' differences from
# it, or (four values) as the first, two differences and the fourth's difference from the plane
# through the first three, takes the cheapest, and prints one PREDICT line per build. Charged,
# each pack of two or more values pays PREDICT_CHOICE bits for the choice (default 1) and a
# predicted one PREDICT_WIDTH bits for its second width (default 4); free, both 0. The
# prediction uses nothing outside the pack, so equal packs stay equal. It is not a scheme
# parameter.
#   scripts/ablations/delta-dag-value-prediction.sh [resolutions, default "4K 16K"]
# shellcheck source=scripts/ablations/patched-build.sh
source "$(dirname "$0")/patched-build.sh"
resolutions=${1:-4K 16K}
build_at value-prediction 615258a delta-dag-value-prediction.patch
sb=$work/value-prediction-build/harness/shadowbench
for r in $resolutions; do
  for build in "city:full closed" "terrain:full closed" "tangle:full closed" "forest:full static"; do
    read -r scene mode <<<"$build"
    for cost in charged free; do
      setting=()
      [ "$cost" = charged ] || setting=(PREDICT_CHOICE=0 PREDICT_WIDTH=0)
      echo "$r $scene $cost: $(env "${setting[@]}" "$sb" build --scheme delta-dag -s "$scene" \
        -m "$mode" -r "$r" --no-bench --no-verify --results "$work/records" 2>&1 | grep PREDICT)"
    done
  done
done
