#!/usr/bin/env bash
# Configures and builds the sanitized build into build-sanitized/: clang, ASan + UBSan on every
# target, the unit tests and the libFuzzer harnesses (fuzz/); no benchmarks and no system tests
# (tests/: many processes, minutes each, what build/ runs). Usage: scripts/build_sanitized.sh [cmake args]
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$PWD}" CCACHE_NOHASHDIR="${CCACHE_NOHASHDIR:-1}"
CC=clang CXX=clang++ cmake -S . -B build-sanitized -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCAIRN_SANITIZE=ON \
  -DCAIRN_BUILD_BENCH=OFF -DCAIRN_BUILD_SYSTEM_TESTS=OFF "$@" >/dev/null
cmake --build build-sanitized -j"$jobs"
