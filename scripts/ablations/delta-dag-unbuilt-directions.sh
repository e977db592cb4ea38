#!/usr/bin/env bash
# Ablation behind delta-dag's README "Topology-only sharing and value prediction, measured before
# building them": what the issue's two directions that are not built could save. Commit 615258a
# with each of two patches; after the layout, the encode step prints one line per build. It is
# not a scheme parameter.
# - delta-dag-topology-sharing.patch (TOPOLOGY): each pack's private tree estimated (a mean
#   header, fitted value widths, its pointers); over the trees in layout order, every tree whose
#   topology (every pack's flags, its children's topologies and the symmetries they are read
#   under) came before gives up its headers and private pointers for one address where they take
#   more bits, and keeps its values. "kept" (TOPO_WIDTHS set): each replaced pack with values
#   still pays for its value width and shift (the entropy of those pairs over such packs); "free":
#   nothing. Finding an occurrence's values costs nothing in either: both are upper bounds.
# - delta-dag-value-prediction.patch (PREDICT): each pack's values as stored (one width and one
#   shift), as the first and the others' differences from it, or (four values) as the first, two
#   differences and the fourth's difference from the plane through the first three, the cheapest
#   taken. "charged": a pack of two or more values pays PREDICT_CHOICE bits for the choice
#   (default 1) and a predicted one PREDICT_WIDTH bits for its second width (default 4); "free":
#   both 0. Nothing outside the pack is used, so equal packs stay equal.
#   scripts/ablations/delta-dag-unbuilt-directions.sh [resolutions, default "4K 16K"]
# shellcheck source=scripts/ablations/patched-build.sh
source "$(dirname "$0")/patched-build.sh"
resolutions=${1:-4K 16K}
build_at topology-sharing 615258a delta-dag-topology-sharing.patch
build_at value-prediction 615258a delta-dag-value-prediction.patch
# Each count: its build, the line it prints, its variant and the variant's settings.
counts=("topology-sharing TOPOLOGY free" "topology-sharing TOPOLOGY kept TOPO_WIDTHS=1"
  "value-prediction PREDICT charged" "value-prediction PREDICT free PREDICT_CHOICE=0 PREDICT_WIDTH=0")
for r in $resolutions; do
  for build in "city:full closed" "terrain:full closed" "tangle:full closed" "forest:full static"; do
    read -r scene mode <<<"$build"
    for count in "${counts[@]}"; do
      read -r name line variant settings <<<"$count"
      read -ra setting <<<"$settings"
      echo "$r $scene $variant: $(env "${setting[@]}" "$work/$name-build/harness/shadowbench" build \
        --scheme delta-dag -s "$scene" -m "$mode" -r "$r" --no-bench --no-verify \
        --results "$work/records" 2>&1 | grep "$line")"
    done
  done
done
