#!/usr/bin/env bash
# Ablation behind delta-dag's README "Topology-only sharing and value prediction, measured before
# building them": how many bits a private tree could give up by pointing to another tree of the
# same topology (every pack's flags, its children's topologies and the symmetries they are read
# under) while keeping its own values, as DAG-MH shares topology alone. Commit 615258a with
# delta-dag-topology-sharing.patch: after the layout, the encode step estimates each pack's
# private tree (a mean header, fitted value widths, its pointers) and, over the trees in layout
# order, replaces every tree whose topology came before where its headers and private pointers
# take more bits than one address, and prints one TOPOLOGY line per build. Widths kept
# (TOPO_WIDTHS set): each replaced tree's packs with values keep their value widths and shifts
# (the entropy of those pairs over such packs, each); free: they keep nothing. Finding an
# occurrence's values costs nothing in either: both are upper bounds. It is not a scheme
# parameter.
#   scripts/ablations/delta-dag-topology-sharing.sh [resolutions, default "4K 16K"]
# shellcheck source=scripts/ablations/patched-build.sh
source "$(dirname "$0")/patched-build.sh"
resolutions=${1:-4K 16K}
build_at topology-sharing 615258a delta-dag-topology-sharing.patch
sb=$work/topology-sharing-build/harness/shadowbench
for r in $resolutions; do
  for build in "city:full closed" "terrain:full closed" "tangle:full closed" "forest:full static"; do
    read -r scene mode <<<"$build"
    for widths in free kept; do
      setting=()
      [ "$widths" = free ] || setting=(TOPO_WIDTHS=1)
      echo "$r $scene widths $widths: $(env "${setting[@]}" "$sb" build --scheme delta-dag \
        -s "$scene" -m "$mode" -r "$r" --no-bench --no-verify --results "$work/records" 2>&1 |
        grep TOPOLOGY)"
    done
  done
done
