// 2D SLAM throughput on real logs (local SLAM + loop closure, the core cairn_slam runs): scans per
// second, real-time factor and peak memory over the whole MIT CSAIL raw log (1988 scans, 424 s) and
// the Intel and ACES corrected logs with seeded odometry noise (peak RSS is the process's, so it
// grows monotonically over the benchmarks run). Accuracy: see tools/slam (cairn_slam_eval).
#include <benchmark/benchmark.h>

#include <fstream>

#include "tools/slam/slam_runner.h"

namespace {

void run_log(benchmark::State& state, const std::string& relative_path, bool corrected) {
  const std::string path = std::string(CAIRN_SHARED_DATA_DIR) + "/" + relative_path;
  if (!std::ifstream(path)) {
    state.SkipWithError(("data absent: " + path).c_str());
    return;
  }
  const cairn::CarmenLog log = cairn::read_carmen_log(path);
  cairn::slam::SlamRunStats stats;
  for (auto _ : state) {
    const auto result = cairn::slam::run_slam(log, corrected, cairn::slam::SlamRunOptions{});
    stats = result.stats;
    benchmark::DoNotOptimize(result.trajectory.data());
  }
  state.counters["scans_per_s"] = stats.scans_per_s();
  state.counters["real_time_x"] = stats.real_time_factor();
  state.counters["slam_cpu_s"] = stats.slam_cpu_s;
  state.counters["loop_closures"] = stats.loop_closures;
  state.counters["loop_searches"] = stats.loop_searches;
  state.counters["peak_rss_mb"] = cairn::slam::peak_rss_mb();
}

void BM_LocalSlamMitCsailRaw(benchmark::State& state) { run_log(state, "carmen/mit-csail/mit-csail.clf", false); }
void BM_LocalSlamIntelNoisy(benchmark::State& state) { run_log(state, "carmen/intel/intel.gfs.log", true); }
void BM_LocalSlamAcesNoisy(benchmark::State& state) { run_log(state, "carmen/aces/aces-corrected.log.gz", true); }
BENCHMARK(BM_LocalSlamMitCsailRaw)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_LocalSlamIntelNoisy)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_LocalSlamAcesNoisy)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
