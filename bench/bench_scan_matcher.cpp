// Local SLAM throughput (scans/second) over the first 300 scans of the Intel Research Lab log.
#include <benchmark/benchmark.h>

#include "robot_agent/core/local_slam.h"
#include "robot_agent/core/test_util.h"

namespace {

void BM_LocalSlamIntel300(benchmark::State& state) {
  const std::string path = std::string(CAIRN_SHARED_DATA_DIR) + "/carmen/intel/intel.gfs.log";
  const auto scans = cairn::agent::testing::read_carmen_flaser(path, 300);
  if (!scans || scans->empty()) {
    state.SkipWithError(("data absent: " + path).c_str());
    return;
  }
  int64_t processed = 0;
  for (auto _ : state) {
    cairn::agent::LocalSlam slam;
    for (const auto& s : *scans) {
      // The log's odometry fields are the corrected poses here; feed them as odometry.
      benchmark::DoNotOptimize(slam.add_scan(s.scan, s.pose));
    }
    processed += int64_t(scans->size());
  }
  state.counters["scans_per_s"] = benchmark::Counter(double(processed), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_LocalSlamIntel300)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
