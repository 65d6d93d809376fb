#!/usr/bin/env bash
# Set-up on Debian 12: installs the missing packages, builds, then
#   demo: runs vdb_interfaces on the bundled frog segmentation,
#   test: runs the whole test suite.
# Usage: bash tools/setup.sh demo|test      (BUILD_DIR, JOBS may be set)
set -euo pipefail

mode=${1:-}
if [[ $mode != demo && $mode != test ]]; then
    echo "usage: bash tools/setup.sh demo|test" >&2
    exit 2
fi

cd "$(dirname "${BASH_SOURCE[0]}")/.."
build=${BUILD_DIR:-build}
jobs=${JOBS:-$(nproc)}

packages=(build-essential cmake ninja-build
          libopenvdb-dev libboost-iostreams-dev libtbb-dev libblosc-dev zlib1g-dev
          libopenmesh-dev libnanoflann-dev libcli11-dev nlohmann-json3-dev
          libgtest-dev libbenchmark-dev)
missing=()
for p in "${packages[@]}"; do
    [[ $(dpkg-query -W -f='${Status}' "$p" 2>/dev/null) == *" ok installed" ]] || missing+=("$p")
done
if ((${#missing[@]})); then
    echo "setup: installing ${missing[*]}"
    sudo=()
    if ((EUID != 0)); then
        command -v sudo >/dev/null || { echo "setup: run as root or install sudo" >&2; exit 1; }
        sudo=(sudo)
    fi
    "${sudo[@]}" apt-get update
    "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive \
        apt-get install -y --no-install-recommends "${missing[@]}"
fi

cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release
if [[ $mode == demo ]]; then
    cmake --build "$build" -j "$jobs" --target vdb_interfaces
    "$build/tools/vdb_interfaces" tests/data/frogtissue.mhd -o "$build/frog.ply" \
        --per-label "$build/frog_labels" --stats
    out=$(cd "$build" && pwd)
    echo "setup: interfaces in $out/frog.ply, one closed surface per label in $out/frog_labels/"
else
    cmake --build "$build" -j "$jobs"
    ctest --test-dir "$build" --output-on-failure -j "$jobs"
fi
