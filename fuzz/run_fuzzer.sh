#!/usr/bin/env bash
# Runs one libFuzzer harness for a while from its seeds. Usage:
#   fuzz/run_fuzzer.sh HARNESS_BINARY NAME SECONDS WORK_DIR SOURCE_DIR SHARED_DATA_DIR
# Seeds: fuzz/seeds/NAME (committed), the starts of the matching files in ../shared/data or
# worlds/ (absent data is said, not silent), and what the harness writes itself
# (CAIRN_FUZZ_SEEDS). The corpus it grows stays in WORK_DIR/corpus-NAME for the next run; a crash
# or a hang is written as WORK_DIR/NAME-crash-* / -timeout-* and fails the run (exit non-zero).
set -euo pipefail
bin=$1 name=$2 seconds=$3 work=$4 src=$5 data=$6
seeds="$work/seeds-$name" corpus="$work/corpus-$name"
rm -rf "$seeds"
mkdir -p "$seeds" "$corpus"
[[ -d "$src/fuzz/seeds/$name" ]] && cp "$src/fuzz/seeds/$name"/* "$seeds/"

# The first 8 KiB of each file: enough records to show every field, short enough to mutate fast.
head_of() {
  local file=$1 out=$2
  if [[ ! -f "$file" ]]; then
    echo "fuzz $name: seed $file is absent (../shared/data not here?); fuzzing without it"
    return
  fi
  case "$file" in
    *.gz) { gzip -dc "$file" || true; } | head -c 8192 > "$seeds/$out" ;;
    *) head -c 8192 "$file" > "$seeds/$out" ;;
  esac
}
case "$name" in
  carmen_log)
    head_of "$data/carmen/intel/intel.gfs.log" intel.log
    head_of "$data/carmen/mit-csail/mit-csail.clf" csail.clf
    head_of "$data/carmen/aces/aces-corrected.log.gz" aces.log
    # and one gzip stream, as the reader takes .gz logs
    [[ -f "$seeds/intel.log" ]] && gzip -c "$seeds/intel.log" > "$seeds/intel.log.gz" ;;
  g2o)
    head_of "$data/g2o_2d/intel.g2o" intel.g2o
    head_of "$data/g2o_2d/input_M3500_g2o.g2o" m3500.g2o ;;
  world)
    for w in "$src"/worlds/*.yaml; do cp "$w" "$seeds/"; done ;;
esac

export CAIRN_FUZZ_SEEDS="$seeds"
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1}"
cd "$work"
exec "$bin" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 \
  -artifact_prefix="$work/$name-" "$corpus" "$seeds"
