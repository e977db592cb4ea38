#!/usr/bin/env bash
# Ablation behind delta-dag's README "What is left" (tried and not kept): the format decode table
# two-level, as zlib's inflate (a root of 9 bits, subtables for longer codes), against the one
# table of 2^longest entries. Commit 69a54d0 built as it is and with
# delta-dag-two-level-decoder.patch; the tangle closed at 16K², delta-dag alone, the two builds
# alternating three times: size and point lookups (ns, one thread) of each run.
#   scripts/ablations/delta-dag-two-level-decoder.sh [resolution, default 16K]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
repo=$(git -C "$here" rev-parse --show-toplevel)
resolution=${1:-16K}
work=$(mktemp -d)
trap 'for v in one two; do git -C "$repo" worktree remove --force "$work/$v" 2>/dev/null; done; rm -rf "$work"' EXIT
for v in one two; do
  git -C "$repo" worktree add --detach "$work/$v" 69a54d0 >/dev/null
  [ $v = one ] || git -C "$work/$v" apply "$here/delta-dag-two-level-decoder.patch"
  if ! { cmake -S "$work/$v" -B "$work/$v-build" -DCMAKE_BUILD_TYPE=Release &&
    cmake --build "$work/$v-build" --target shadowbench -j"$(nproc)"; } >"$work/$v.log" 2>&1; then
    tail -n 40 "$work/$v.log" >&2
    exit 1
  fi
done
for run in 1 2 3; do
  for v in one two; do
    echo "run $run, $v-level table:"
    "$work/$v-build/harness/shadowbench" build --scheme delta-dag -s tangle:full -m closed \
      -r "$resolution" --no-verify --results "$work/records-$v-$run" 2>&1 |
      grep -E "MiB in|lookup (uniform|view) +1×1"
  done
done
