#!/usr/bin/env bash
# Ablation behind delta-dag's README "What bounds a point lookup": five changes to the point walk
# measured on the two cells whose point lookups miss the goal on some machines (the forest static
# and the city open at 16K²) and not kept. Each patch on 235ae18 gives a build whose structures
# take the change where SB_PROBE_LIST holds a 1 for them (one digit per structure, in the order
# loaded), so `shadowbench bench DAG-MH S S S S` runs the structure with and without it in one
# process, in turn, on the same queries (9 rounds; the ratios to `dag-mh`'s):
#   delta-dag-direct-formats.patch  a table of 2^longest formats indexed by the code's bits, so a
#                                   step loads its format in one read, not two (no decode entry);
#   delta-dag-compact-formats.patch formats of 16 bytes, 16-aligned (fields' places and the pack's
#                                   end in 2-byte words; pointer widths derived), not 22;
#   delta-dag-flat-step.patch       a step that selects rather than branches (shared or private
#                                   child, a value or none, a turned reference or not);
#   delta-dag-fixed-walk.patch      a walk of one step a level down to the texels, a finished walk
#                                   stepping again in place, so that the loop's end is known and
#                                   the next lookup's reads may start before this one's end;
#   delta-dag-min-uses.patch        SB_MIN_USES=4 at build: the format table takes formats used 4
#                                   times (not 8), so fewer packs escape (built, then timed beside).
#   scripts/ablations/delta-dag-lookup-probes.sh [resolution, default 16K]
# shellcheck source=scripts/ablations/patched-build.sh
source "$(dirname "$0")/patched-build.sh"
resolution=${1:-16K}
for probe in direct-formats compact-formats flat-step fixed-walk min-uses; do
  build_at "$probe" 235ae18 "delta-dag-$probe.patch"
done
for cell in "forest:full static" "city:full open"; do
  read -r scene mode <<<"$cell"
  sb=$work/min-uses-build/harness/shadowbench
  for variant in dag-mh delta-dag min-uses; do
    scheme=${variant/min-uses/delta-dag}
    min_uses=8
    [ "$variant" != min-uses ] || min_uses=4
    SB_MIN_USES=$min_uses "$sb" build --scheme "$scheme" -s "$scene" -m "$mode" -r "$resolution" \
      --no-bench --no-verify --results "$work/records-${scene%%:*}-$variant" -o "$work/$variant.sb" \
      >/dev/null
  done
  for probe in direct-formats compact-formats flat-step fixed-walk; do
    echo "## $scene $mode $resolution², $probe: dag-mh, delta-dag without, with, without, with"
    (cd "$work" && SB_PROBE_LIST=0101 "$work/$probe-build/harness/shadowbench" bench dag-mh.sb \
      delta-dag.sb delta-dag.sb delta-dag.sb delta-dag.sb -s "$scene" --filters 1,9 --rounds 9)
  done
  echo "## $scene $mode $resolution², formats used 8 and 4 times: dag-mh, delta-dag, min-uses"
  (cd "$work" && "$sb" bench dag-mh.sb delta-dag.sb min-uses.sb -s "$scene" --filters 1,9 \
    --rounds 9)
  for variant in delta-dag min-uses; do
    /usr/bin/python3 - "$variant" "$work/records-${scene%%:*}-$variant"/*.json <<'PY'
import json, sys
record = json.load(open(sys.argv[2]))
counters = record["counters"]
print(f"{sys.argv[1]}: {record['size_bytes']['total'] / 2**20:.3f} MiB, "
      f"{counters['pack formats']} formats, {counters['explicit formats']} explicit")
PY
  done
done
