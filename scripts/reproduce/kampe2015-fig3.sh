#!/usr/bin/env bash
# Kämpe et al. 2015, Fig. 3 and §5.3: a `cpvs-fast` structure for each of 165 spot lights over
# city:full (≈ ClosedCity) at 8K³ each with logarithmic depth (eq. 1), the distribution of their sizes
# and build times with the paper's figures beside, and all lights evaluated for one view with a
# light list per 8×8 screen tile. Writes results/reproduce/kampe2015-fig3.md; resumes per light.
# --max-resolution caps the 8K per light (all-cpvs.sh passes its 64K through).
# With --stand-ins calibrated, over city:cityscape into results/reproduce/calibrated/.
#   scripts/reproduce/kampe2015-fig3.sh [--max-resolution 8K] [--stand-ins full|calibrated] [many-lights options, e.g. --lights 40]
set -euo pipefail
cd "$(dirname "$0")/../.."
resolution=8K
stand_ins=full
args=()
while [ $# -gt 0 ]; do
  case $1 in
    --max-resolution) resolution=$2; shift 2 ;;
    --max-resolution=*) resolution=${1#*=}; shift ;;
    --stand-ins) stand_ins=$2; shift 2 ;;
    --stand-ins=*) stand_ins=${1#*=}; shift ;;
    --no-bench) shift ;; # the sweep option all-cpvs.sh may pass; many-lights times no lookups
    *) args+=("$1"); shift ;;
  esac
done
texels() { local d=${1%[kK]}; if [ "$d" != "$1" ]; then echo $((10#$d * 1024)); else echo $((10#$d)); fi; }
[[ $resolution =~ ^[0-9]{1,7}[kK]?$ ]] || { echo "kampe2015-fig3: bad --max-resolution '$resolution'" >&2; exit 2; }
(($(texels "$resolution") < 8192)) || resolution=8K
case $stand_ins in
  full) scene=city:full; out=results/reproduce ;;
  calibrated) scene=city:cityscape; out=results/reproduce/calibrated ;;
  *) echo "kampe2015-fig3: --stand-ins '$stand_ins' must be full or calibrated" >&2; exit 2 ;;
esac
scripts/install-deps.sh
build_dir=${SHADOWBENCH_BUILD:-build}
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build_dir" -j "$(nproc)" --target shadowbench
"$build_dir/harness/shadowbench" many-lights --scene "$scene" --lights 165 --scheme cpvs-fast \
  -m closed -r "$resolution" --out "$out/kampe2015-fig3" "${args[@]}"
cp "$out/kampe2015-fig3/summary.md" "$out/kampe2015-fig3.md"
echo "wrote $out/kampe2015-fig3.md"
