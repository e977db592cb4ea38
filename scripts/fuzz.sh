#!/usr/bin/env bash
# A time-boxed fuzzing campaign (issue 11): builds the libFuzzer targets of fuzz/ in build-fuzz/
# (clang, ASan + UBSan) and runs each in turn from its seeds in fuzz/corpus/<target>/.
#   scripts/fuzz.sh [SECONDS [FLAG…]]   SECONDS per target, default 60; FLAGs go to libFuzzer
# Inputs that add coverage go to build-fuzz/corpus/<target>/, a crashing input (crash, sanitizer
# report, leak, over 2 GiB, over 10 s) to build-fuzz/crashes/<target>/ and the run's log to
# build-fuzz/logs/<target>.log. Exits 1 when any target crashed. A target stops at its first
# crash; `scripts/fuzz.sh 600 -fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1` fuzzes
# on past them for the whole time box and keeps every crashing input.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
shift $(($# > 0 ? 1 : 0))
flags=("$@")
build=build-fuzz

# shellcheck source=scripts/compiler-cache.sh
source scripts/compiler-cache.sh
mkdir -p "$build/logs"
if ! CC=clang CXX=clang++ cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DSHADOWBENCH_FUZZ=ON "${launcher[@]}" >"$build/logs/configure.log" 2>&1; then
  cat "$build/logs/configure.log" >&2
  exit 1
fi
cmake --build "$build" -j "$(nproc)" --target fuzz_structure_file fuzz_scheme_payload \
  fuzz_part_payload fuzz_scene_file fuzz_model_file fuzz_query_line >/dev/null
export LSAN_OPTIONS="suppressions=$PWD/fuzz/lsan.supp:print_suppressions=0"

failed=()
# Seeds and known crashes (fuzz/regressions/) first: a bug that came back fails without luck.
if ! ctest --test-dir "$build" -R '^fuzz_replay_' >"$build/logs/replay.log" 2>&1; then
  echo "replay of fuzz/corpus and fuzz/regressions failed: see $build/logs/replay.log"
  grep -E '^[[:space:]]*[0-9]+ - ' "$build/logs/replay.log" || true
  failed+=(replay)
fi
# fuzz TARGET BINARY [VAR=value…]: one time-boxed run, its summary on one line.
fuzz() {
  local target=$1 binary=$2
  shift 2
  mkdir -p "$build/corpus/$target" "$build/crashes/$target"
  local log="$build/logs/$target.log" status=0 crashes_before crashes
  crashes_before=$(find "$build/crashes/$target" -type f | wc -l)
  env "$@" "$build/fuzz/$binary" "$build/corpus/$target" "fuzz/corpus/$target" \
    -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 -print_final_stats=1 \
    -artifact_prefix="$build/crashes/$target/" "${flags[@]}" >"$log" 2>&1 || status=$?
  crashes=$(($(find "$build/crashes/$target" -type f | wc -l) - crashes_before))
  # The final statistics, or in fork mode (no statistics) the last status line over the time box.
  local executions rate coverage
  executions=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log")
  if [ -z "$executions" ]; then
    executions=$(grep -o '^#[0-9]*' "$log" | tail -n 1 | tr -d '#')
    rate=$((${executions:-0} / seconds))
  fi
  coverage=$(grep -o 'cov: [0-9]*' "$log" | tail -n 1 | cut -d' ' -f2)
  printf '%-24s %10s runs %8s/s  cov %6s  ' "$target" "${executions:-?}" "${rate:-?}" \
    "${coverage:-?}"
  if [ "$status" -eq 0 ] && [ "$crashes" -eq 0 ]; then
    echo ok
  else
    echo "CRASH (exit $status, $crashes new inputs):" \
      "$(grep -m1 -E '^(==[0-9]+==ERROR|SUMMARY)' "$log" || true); see $log"
    failed+=("$target")
  fi
}

fuzz structure_file fuzz_structure_file
# Every registered scheme has a golden file (interface_test checks it), hence a payload target;
# the golden files of parameter variants (<scheme>_<param>-<value>.sb) add none.
for golden in tests/golden/*.sb; do
  scheme=$(basename "$golden" .sb)
  [[ $scheme == *_* ]] && continue
  fuzz "payload-$scheme" fuzz_scheme_payload SHADOWBENCH_FUZZ_SCHEME="$scheme"
done
# Every scheme that builds in parts has a seed folder, hence a part payload target.
for seeds in fuzz/corpus/part-*/; do
  target=$(basename "$seeds")
  fuzz "$target" fuzz_part_payload SHADOWBENCH_FUZZ_SCHEME="${target#part-}"
done
fuzz scene_file fuzz_scene_file
fuzz model_file fuzz_model_file
fuzz query_line fuzz_query_line

if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz: failed: ${failed[*]} (crashing inputs in $build/crashes/)" >&2
  exit 1
fi
