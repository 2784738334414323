#!/usr/bin/env bash
# The whole test suite: installs the stack, builds, runs every unit and integration test (ctest).
# Tests whose data in ../shared/data is absent skip loudly (ctest lists them as skipped).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install_deps.sh
./scripts/build.sh
jobs=$(nproc 2>/dev/null || echo 2)
cd build
ctest --output-on-failure -j"$jobs" "$@"
