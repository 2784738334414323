#!/usr/bin/env bash
# Runs every libFuzzer harness (fuzz/) for SECONDS each, two at a time, from the sanitized build;
# the corpora grow in build-sanitized/fuzz/ and are kept for the next run. Prints each harness's
# runs, coverage and corpus, and any crash or hang it found (then exits 1).
# Usage: scripts/fuzz.sh [SECONDS] [HARNESS ...]   (default 300 s, every harness)
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-300}
shift || true
./scripts/build_sanitized.sh >/dev/null
work=$PWD/build-sanitized/fuzz
mkdir -p "$work"
names=("$@")
if [[ ${#names[@]} == 0 ]]; then
  for bin in "$work"/../bin/fuzz_*; do names+=("$(basename "$bin" | sed 's/^fuzz_//')"); done
fi
data=$(cd .. && pwd)/shared/data
fuzz_one() {
  local name=$1
  if fuzz/run_fuzzer.sh "$work/../bin/fuzz_$name" "$name" "$seconds" "$work" "$PWD" "$data" \
    > "$work/$name.log" 2>&1; then
    echo "$name: $(grep -E '^stat::number_of_executed_units' "$work/$name.log" | awk '{print $2}') runs," \
      "$(grep -oE 'cov: [0-9]+' "$work/$name.log" | tail -1), corpus $(ls "$work/corpus-$name" | wc -l) inputs, nothing found"
  else
    echo "$name: FOUND a crash or hang: $(ls "$work/$name"-* 2>/dev/null | tr '\n' ' ') (log: $work/$name.log)"
    return 1
  fi
}
status=0
jobs=$(nproc 2>/dev/null || echo 2)
for ((i = 0; i < ${#names[@]}; i += jobs)); do
  pids=()
  for name in "${names[@]:i:jobs}"; do
    fuzz_one "$name" &
    pids+=($!)
  done
  for pid in "${pids[@]}"; do wait "$pid" || status=1; done
done
exit $status
