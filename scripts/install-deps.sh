#!/usr/bin/env bash
# Installs the Debian packages shadowbench needs, only those missing (idempotent).
set -euo pipefail
packages=(build-essential cmake libembree-dev libtbb-dev libglm-dev libfmt-dev libopenexr-dev
          catch2 libbenchmark-dev libassimp-dev libcli11-dev nlohmann-json3-dev libxxhash-dev
          libzstd-dev libpng-dev libopenvdb-dev libboost-iostreams-dev python3-matplotlib
          python3-jsonschema git clang libclang-rt-14-dev snakemake ccache
          python3-markdown chromium)  # scripts/report.py, and its test in a headless browser
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
echo "installing: ${missing[*]}"
sudo_=""
[ "$(id -u)" -ne 0 ] && sudo_="sudo"
$sudo_ apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo_ apt-get install -y -qq "${missing[@]}" >/dev/null
