// The agent's outbox (robot_agent/app/outbox.h): what keeping each keyframe on disk costs the
// agent's loop, what deleting acknowledged ones costs, and how long a restarted agent takes to
// read back an earlier run's undelivered records. Records are 5 KB, about a keyframe with its
// compressed scan as the agent sends it.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <filesystem>

#include "robot_agent/app/outbox.h"

namespace {

using cairn::RobotId;
using cairn::agent::Outbox;
using cairn::agent::OutboxItem;
using cairn::agent::OutboxKind;

constexpr int kRecordBytes = 5000;

struct FreshOutbox {
  std::string path = "/tmp/bench_outbox_" + std::to_string(getpid()) + ".sqlite";
  std::unique_ptr<Outbox> outbox;
  std::string error;
  FreshOutbox() {
    remove();
    outbox = Outbox::open(path, RobotId(0), &error);
  }
  ~FreshOutbox() {
    outbox.reset();
    remove();
  }
  void remove() const {
    for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path + suffix);
  }
};

OutboxItem keyframe(int32_t seq) {
  return OutboxItem{OutboxKind::kKeyframe, seq, std::vector<uint8_t>(kRecordBytes, 7)};
}

/// One keyframe kept (a transaction), then, every arg 0 keyframes, the acknowledged ones deleted.
void BM_KeepKeyframe(benchmark::State& state) {
  FreshOutbox o;
  if (!o.outbox) return state.SkipWithError(o.error.c_str());
  int32_t seq = 0;
  for (auto _ : state) {
    if (!o.outbox->put(1, {keyframe(seq)}, &o.error)) state.SkipWithError(o.error.c_str());
    if (++seq % state.range(0) == 0 && !o.outbox->acknowledged(1, seq - 1, &o.error))
      state.SkipWithError(o.error.c_str());
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_KeepKeyframe)->Arg(1)->Arg(10)->Unit(benchmark::kMicrosecond);

/// A restarted agent reading back an earlier run's arg 0 undelivered keyframes.
void BM_ReadEarlierRun(benchmark::State& state) {
  FreshOutbox o;
  if (!o.outbox) return state.SkipWithError(o.error.c_str());
  std::vector<OutboxItem> items;
  for (int32_t seq = 0; seq < state.range(0); ++seq) items.push_back(keyframe(seq));
  if (!o.outbox->put(1, items, &o.error)) return state.SkipWithError(o.error.c_str());
  for (auto _ : state) {
    auto earlier = o.outbox->earlier_sessions(2, &o.error);
    benchmark::DoNotOptimize(earlier);
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_ReadEarlierRun)->Arg(100)->Arg(1000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
