#!/usr/bin/env bash
# Ablation behind delta-dag's README "Skip table": the table's level forced at load
# (SB_SKIP_LEVEL, read by delta-dag-skip-level.patch) on structures saved once, beside dag-mh's.
# Commit 9e96be7 built with the patch; per scene (tangle, city, terrain closed) both schemes built
# and saved, then `shadowbench bench` of dag-mh and of delta-dag at levels 5 to 8, in turn, twice:
# point lookups and 9×9 PCF (ns, one thread).
#   scripts/ablations/delta-dag-skip-level.sh [resolution, default 16K]
# shellcheck source=scripts/ablations/patched-build.sh
source "$(dirname "$0")/patched-build.sh"
resolution=${1:-16K}
build_at skip 9e96be7 delta-dag-skip-level.patch
shadowbench=$work/skip-build/harness/shadowbench
for scene in tangle city terrain; do
  for scheme in dag-mh delta-dag; do
    "$shadowbench" build --scheme "$scheme" -s "$scene:full" -m closed -r "$resolution" \
      --no-bench --no-verify --results "$work/records" -o "$work/$scene-$scheme.sb" >/dev/null
  done
  for run in 1 2; do
    echo "$scene $resolution, run $run, dag-mh:"
    "$shadowbench" bench "$work/$scene-dag-mh.sb" -s "$scene:full" | grep -E "1×1|9×9"
    for level in 5 6 7 8; do
      echo "$scene $resolution, run $run, delta-dag at skip level $level:"
      SB_SKIP_LEVEL=$level "$shadowbench" bench "$work/$scene-delta-dag.sb" -s "$scene:full" |
        grep -E "1×1|9×9"
    done
  done
done
