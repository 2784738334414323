// The base station's journal (base_station/store): what storing a poll's samples costs before they
// can be acknowledged, and how long a restarted base takes to read a whole mission back.
// Records are 1 KB, about a keyframe with a 360-beam scan (docs/architecture.md, message sizes).
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <filesystem>

#include "base_station/store/journal.h"

namespace {

using cairn::RobotId;
using cairn::base::Journal;
using cairn::base::JournalKind;
using cairn::base::JournalOptions;
using cairn::base::JournalRecord;

std::string fresh_journal(const std::string& name) {
  const std::string path = "/tmp/bench_journal_" + std::to_string(getpid()) + "_" + name + ".sqlite";
  for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path + suffix);
  return path;
}

std::vector<JournalRecord> batch(int64_t* next_key, int size, int bytes) {
  std::vector<JournalRecord> out(size);
  for (auto& r : out) {
    r.kind = JournalKind::kKeyframe;
    r.robot = RobotId(int32_t(*next_key % 4));
    r.key = (*next_key)++;
    r.payload.assign(bytes, uint8_t(r.key));
  }
  return out;
}

/// One poll's batch (arg 0 records of 1 KB) committed; sync FULL (arg 1 = 1) or NORMAL.
void BM_AppendBatch(benchmark::State& state) {
  JournalOptions options;
  options.sync_full = state.range(1) == 1;
  const std::string path = fresh_journal("append");
  std::string error;
  auto j = Journal::open(path, options, &error);
  if (!j) {
    state.SkipWithError(error.c_str());
    return;
  }
  int64_t key = 0;
  for (auto _ : state) {
    const auto records = batch(&key, int(state.range(0)), 1024);
    if (!j->append(records, &error)) state.SkipWithError(error.c_str());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
  state.SetBytesProcessed(state.iterations() * state.range(0) * 1024);
  j.reset();
  for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path + suffix);
}
BENCHMARK(BM_AppendBatch)->Args({1, 1})->Args({10, 1})->Args({1, 0})->Args({10, 0})->Unit(benchmark::kMillisecond);

/// A restarted base reading back a mission of arg 0 records.
void BM_LoadMission(benchmark::State& state) {
  const std::string path = fresh_journal("load");
  std::string error;
  auto j = Journal::open(path, {}, &error);
  int64_t key = 0;
  for (int64_t left = state.range(0); left > 0; left -= 500) {
    if (!j->append(batch(&key, int(std::min<int64_t>(left, 500)), 1024), &error)) state.SkipWithError(error.c_str());
  }
  for (auto _ : state) {
    auto contents = j->load(&error);
    benchmark::DoNotOptimize(contents);
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
  j.reset();
  for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path + suffix);
}
BENCHMARK(BM_LoadMission)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
