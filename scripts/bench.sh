#!/usr/bin/env bash
# Installs what is missing, builds Release, runs the default sweep (every scheme on the
# default city, closed mode, 1K–8K, verified and with lookup timings) and prints the tables.
# Extra arguments go to `shadowbench sweep` (e.g. --scenes city,terrain --modes closed,open).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$(nproc)" --target shadowbench
build/harness/shadowbench sweep --out results/sweep "$@"
/usr/bin/python3 scripts/plot.py results/sweep --out results/sweep/plots || echo "plots skipped"
