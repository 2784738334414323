#!/usr/bin/env bash
# Configures and builds Cairn into build/ (ccache on). Usage: scripts/build.sh [extra cmake args]
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)
# ccache hits across checkouts (another clone, a CI folder): paths are hashed relative to the
# checkout, and the working directory is left out of the hash (debug info then names the first
# checkout's paths, which only matters to a debugger).
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$PWD}" CCACHE_NOHASHDIR="${CCACHE_NOHASHDIR:-1}"
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "$@" >/dev/null
cmake --build build -j"$jobs"
