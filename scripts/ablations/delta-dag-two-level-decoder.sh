#!/usr/bin/env bash
# Ablation behind delta-dag's README "What is left" (tried and not kept): the format decode table
# two-level, as zlib's inflate (a root of 9 bits, subtables for longer codes), against the one
# table of 2^longest entries. Commit 69a54d0 built as it is and with
# delta-dag-two-level-decoder.patch; the tangle closed at 16K², delta-dag alone, the two builds
# alternating three times: size and point lookups (ns, one thread) of each run.
#   scripts/ablations/delta-dag-two-level-decoder.sh [resolution, default 16K]
# shellcheck source=scripts/ablations/patched-build.sh
source "$(dirname "$0")/patched-build.sh"
resolution=${1:-16K}
build_at one 69a54d0
build_at two 69a54d0 delta-dag-two-level-decoder.patch
for run in 1 2 3; do
  for v in one two; do
    echo "run $run, $v-level table:"
    "$work/$v-build/harness/shadowbench" build --scheme delta-dag -s tangle:full -m closed \
      -r "$resolution" --no-verify --results "$work/records-$v-$run" 2>&1 |
      grep -E "MiB in|lookup (uniform|view) +1×1"
  done
done
