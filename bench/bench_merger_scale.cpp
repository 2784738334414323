// Merger scale (issue: "time per incremental update against graph size, 10 robots up to 20,000
// keyframes; aim for at most 100 ms per update at 10,000 keyframes"). A synthetic team of 10
// robots, each linked by a start hint, drives a noisy random walk; every keyframe is followed by
// MultiRobotMapper::optimize() (the base's incremental update). Prints the curve: mean and max ms
// per update over each 1,000-keyframe window, plus the cost of a full global-map render.
// Usage: bench_merger_scale [total_keyframes=20000] [beams=90]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "base_station/core/multi_robot_mapper.h"

namespace {

using cairn::Keyframe;
using cairn::KeyframeId;
using cairn::RobotId;
using cairn::SE2;

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

/// A keyframe of robot `robot` at local pose `pose` with a small synthetic scan (a circular room).
Keyframe make_keyframe(RobotId robot, int seq, const SE2& prev, const SE2& pose, int beams) {
  Keyframe kf;
  kf.id = KeyframeId{robot, seq};
  kf.stamp_ns = cairn::StampNs(seq + 1) * cairn::kNsPerSec;
  kf.T_local_base = pose;
  kf.T_prev_this = prev.between(pose);
  kf.edge_covariance = cairn::Covariance3::Identity() * 1e-3;
  kf.scan.angle_min_rad = float(-M_PI);
  kf.scan.angle_increment_rad = float(2 * M_PI / beams);
  kf.scan.range_max_m = 12.f;
  for (int i = 0; i < beams; ++i) kf.scan.ranges_m.push_back(3.f + 0.5f * float(std::sin(0.1 * i + seq)));
  return kf;
}

}  // namespace

int main(int argc, char** argv) {
  const int total = argc > 1 ? std::atoi(argv[1]) : 20000;
  const int beams = argc > 2 ? std::atoi(argv[2]) : 90;
  const int robots = 10, window = 1000;
  cairn::base::MapperOptions options;
  options.detect_loops = false;  // place recognition is benchmarked per query elsewhere
  cairn::base::MultiRobotMapper mapper(options);
  std::mt19937 rng(42);
  std::normal_distribution<double> turn(0.0, 0.3);
  std::vector<SE2> pose(robots);
  std::vector<int> seq(robots, 0);
  for (int r = 0; r < robots; ++r) mapper.set_robot_start(RobotId(r), SE2(30.0 * r, 0, 0));
  std::printf("keyframes  mean_ms  max_ms  (per add_keyframe + optimize, %d robots)\n", robots);
  double sum = 0, worst = 0;
  for (int k = 0; k < total; ++k) {
    const int r = k % robots;
    const SE2 next = pose[size_t(r)] * SE2(0.5, 0.0, turn(rng));
    const auto t0 = std::chrono::steady_clock::now();
    mapper.add_keyframe(make_keyframe(RobotId(r), seq[size_t(r)]++, pose[size_t(r)], next, beams));
    mapper.optimize();
    const double ms = ms_since(t0);
    pose[size_t(r)] = next;
    sum += ms;
    worst = std::max(worst, ms);
    if ((k + 1) % window == 0) {
      std::printf("%9d  %7.2f  %6.2f\n", k + 1, sum / window, worst);
      std::fflush(stdout);
      sum = worst = 0;
    }
  }
  const auto t0 = std::chrono::steady_clock::now();
  const double area = mapper.mapped_area_m2();
  std::printf("global map render of %d keyframes: %.0f ms (%.0f m2)\n", total, ms_since(t0), area);
  return 0;
}
