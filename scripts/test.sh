#!/usr/bin/env bash
# The whole test suite: installs the stack, builds, runs every unit and integration test (ctest in
# build/), and the unit tests again under ASan + UBSan with each fuzz harness for a short while
# (ctest in build-sanitized/, clang; CAIRN_SANITIZED=0 leaves that out). Arguments go to both ctest
# runs (e.g. -R Journal). Tests whose data in ../shared/data is absent skip loudly (ctest lists them
# as skipped).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install_deps.sh
./scripts/build.sh
sanitized=${CAIRN_SANITIZED:-1}
[[ $sanitized == 1 ]] && ./scripts/build_sanitized.sh
jobs=$(nproc 2>/dev/null || echo 2)

run_ctest() {
  local dir=$1
  shift
  (cd "$dir" && ctest --output-on-failure -j"$jobs" "$@") 2>&1 | tee "$dir/ctest.log"
}
summary() { grep -E "tests passed|tests failed out of|No tests were found" "$1/ctest.log" | tail -1; }

main_ok=1
run_ctest build "$@" || main_ok=0

san_ok=1
if [[ $sanitized == 1 ]]; then
  echo "== The unit tests under ASan + UBSan, and the fuzz harnesses (build-sanitized/) =="
  # The suites that replay whole real logs or missions (labels multirobot, slow) run in build/ only.
  # new_delete_type_mismatch=0: Fast DDS 2.9 itself (Debian's libfastrtps) deletes its statistics
  # readers through the RTPSReader base with the base's size, at every participant's end; ASan's
  # interceptors see it in any test that makes a participant. Leaks: third-party only (the file says which).
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=0:new_delete_type_mismatch=0 UBSAN_OPTIONS=print_stacktrace=1 \
    LSAN_OPTIONS=suppressions=$PWD/scripts/lsan_suppressions.txt \
    run_ctest build-sanitized -LE "multirobot|slow" "$@" || san_ok=0
fi

line="build/: $(summary build)"
[[ $sanitized == 1 ]] && line="$line; sanitized + fuzz: $(summary build-sanitized)"
if [[ $main_ok == 1 && $san_ok == 1 ]]; then
  echo "PASS: $line"
else
  echo "FAIL: $line"
  exit 1
fi
