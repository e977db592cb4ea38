#!/usr/bin/env bash
# Installs what is missing, builds, and runs the whole test suite through CTest.
#   scripts/test.sh             Release build in build/, all tests
#   scripts/test.sh --sanitize  AddressSanitizer + UBSan build in build-sanitize/, all tests but
#                               the Snakemake workflow's (it drives the CLI the Release run
#                               checks; its jobs are the `part` and `merge` the other tests cover)
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
# shellcheck source=scripts/compiler-cache.sh
source scripts/compiler-cache.sh
build=build
flags=(-DCMAKE_BUILD_TYPE=Release)
skip=()
if [ "${1:-}" = "--sanitize" ]; then
  build=build-sanitize
  flags=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DSHADOWBENCH_SANITIZE=ON)
  skip=(-LE workflow)
fi
cmake -S . -B "$build" "${flags[@]}" "${launcher[@]}" >/dev/null
cmake --build "$build" -j "$(nproc)"
ctest --test-dir "$build" --output-on-failure -j "$(nproc)" "${skip[@]}"
