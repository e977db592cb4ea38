#!/usr/bin/env bash
# Ablation behind delta-dag's README "Size on the city open" (What is left): how many bits the
# pointers' fields take against the widths of the pointers themselves. A pack gives all its
# shared children one address width and all its private children one distance width (the widest
# of them, rounded up to even in table formats), so a field holds more bits than its own value
# needs. Commit 0854ce8 with delta-dag-address-widths.patch: writing the layout kept counts, per
# kind of pointer, the pointers, their fields' bits and the bits of their values' own widths, and
# prints them. The cells: the city open at 8K², the city closed at 16K², the tangle at 8K².
#   scripts/ablations/delta-dag-address-widths.sh
# shellcheck source=scripts/ablations/patched-build.sh
source "$(dirname "$0")/patched-build.sh"
build_at widths 0854ce8 delta-dag-address-widths.patch
sb=$work/widths-build/harness/shadowbench
for build in "city:full open 8K" "city:full closed 16K" "tangle:full closed 8K"; do
  read -r scene mode resolution <<<"$build"
  echo "$scene $mode $resolution:"
  "$sb" build --scheme delta-dag -s "$scene" -m "$mode" -r "$resolution" --no-bench \
    --no-verify --results "$work/records" 2>&1 | grep -E 'pointers:|MiB'
done
