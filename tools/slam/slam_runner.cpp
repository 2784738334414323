#include "tools/slam/slam_runner.h"

#include <sys/resource.h>

#include <chrono>
#include <string>
#include <unordered_map>

#include "common/errors.h"

namespace cairn::slam {

double process_cpu_s() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

double peak_rss_mb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_maxrss) / 1024.0;  // Linux: kilobytes
}

namespace {

struct ProcessUsage {
  double sys_cpu_s = 0;
  int64_t minor_faults = 0, major_faults = 0;
};

ProcessUsage process_usage() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return {double(u.ru_stime.tv_sec) + 1e-6 * double(u.ru_stime.tv_usec), int64_t(u.ru_minflt), int64_t(u.ru_majflt)};
}

std::vector<SE2> odometry_of(const CarmenLog& log, bool corrected, const OdometryNoiseOptions& noise) {
  std::vector<SE2> poses;
  poses.reserve(log.scans.size());
  // Raw logs: the FLASER pose fields are the wheel odometry. Corrected logs: noise the reference.
  for (const CarmenScan& s : log.scans) poses.push_back(s.T_world_laser);
  return corrected ? add_odometry_noise(poses, noise) : poses;
}

void count(const agent::LocalSlamResult& r, SlamRunStats* s) {
  using S = agent::LocalSlamResult::Status;
  switch (r.status) {
    case S::kFirstScan:
    case S::kMatched:
      ++s->matched;
      break;
    case S::kMotionFiltered:
      ++s->motion_filtered;
      break;
    case S::kMatchFailed:
      ++s->match_failed;
      break;
    case S::kOdometryStalled:
      ++s->odometry_stalled;
      break;
    case S::kTooFewPoints:
      ++s->too_few_points;
      break;
  }
  s->beams += r.filter_stats;
}

}  // namespace

SlamRunResult run_slam(const CarmenLog& log, bool corrected, const SlamRunOptions& options) {
  SlamRunResult out;
  std::vector<SE2> odometry = odometry_of(log, corrected, options.noise);
  if (options.odometry_dropout_first >= 1) {
    const int last = std::min(options.odometry_dropout_last, int(odometry.size()) - 1);
    for (int i = options.odometry_dropout_first; i <= last; ++i) odometry[size_t(i)] = odometry[size_t(i - 1)];
  }
  const auto wall0 = std::chrono::steady_clock::now();
  const double cpu0 = process_cpu_s();
  const ProcessUsage usage0 = process_usage();
  agent::LocalSlam slam(options.slam);
  for (size_t i = 0; i < log.scans.size(); ++i) {
    const CarmenScan& s = log.scans[i];
    const std::optional<SE2> odom = options.use_odometry ? std::optional<SE2>(odometry[i]) : std::nullopt;
    count(slam.add_scan(s.scan, odom), &out.stats);
    ++out.stats.scans;
  }
  slam.finish();
  out.trajectory = slam.optimized_trajectory();
  out.stats.slam_wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  out.stats.slam_cpu_s = process_cpu_s() - cpu0;
  const ProcessUsage usage1 = process_usage();
  out.stats.slam_sys_cpu_s = usage1.sys_cpu_s - usage0.sys_cpu_s;
  out.stats.slam_minor_faults = usage1.minor_faults - usage0.minor_faults;
  out.stats.slam_major_faults = usage1.major_faults - usage0.major_faults;
  for (size_t i = 0; i < log.scans.size(); ++i) out.odometry.push_back({log.scans[i].stamp_ns, odometry[i]});
  if (!log.scans.empty()) out.stats.log_duration_s = ns_to_sec(log.scans.back().stamp_ns - log.scans.front().stamp_ns);
  const agent::SubmapLoopCloser& lc = slam.loop_closure();
  out.stats.nodes = lc.num_nodes();
  out.stats.submaps = lc.graph().num_submaps();
  out.stats.loop_closures = lc.stats().loop_closures;
  out.stats.loop_searches = lc.stats().searches;
  out.stats.anisotropic_loop_closures = lc.stats().anisotropic_loop_closures;
  out.stats.anisotropic_local_nodes = lc.stats().anisotropic_local_nodes;
  out.stats.optimizations = lc.stats().optimizations;
  out.stats.loop_scored_candidates = lc.stats().scored_candidates;
  out.stats.loop_scored_candidates_failed = lc.stats().scored_candidates_failed;
  out.stats.loop_matcher_mb = double(lc.stats().matcher_bytes) / (1024.0 * 1024.0);
  return out;
}

CarmenLog carmen_log_from_robot(const RobotLogData& robot) {
  const std::string who = "robot " + std::to_string(robot.robot.value);
  if (robot.odometry.empty()) throw InputError(who + ": no odometry in the log");
  Trajectory odometry;
  odometry.reserve(robot.odometry.size());
  for (const OdometryReading& o : robot.odometry) odometry.push_back({o.stamp_ns, o.T_odom_base});
  CarmenLog log;
  for (const LaserScan& scan : robot.scans) {
    const std::optional<SE2> pose = interpolate_pose(odometry, scan.stamp_ns);
    if (!pose) continue;
    CarmenScan s;
    s.stamp_ns = scan.stamp_ns;
    s.scan = scan;
    s.T_world_laser = *pose;
    s.T_odom_laser = *pose;
    log.scans.push_back(std::move(s));
  }
  if (log.scans.empty()) throw InputError(who + ": no scan within the odometry's time span");
  return log;
}

OccupancyGrid render_map(const CarmenLog& log, const Trajectory& trajectory, const OccupancyGridOptions& options) {
  std::unordered_map<StampNs, SE2> by_stamp;
  for (const auto& p : trajectory) by_stamp[p.stamp_ns] = p.pose;
  OccupancyGrid grid(options);
  for (const CarmenScan& s : log.scans) {
    const auto it = by_stamp.find(s.stamp_ns);
    if (it != by_stamp.end()) grid.insert_scan(it->second, scan_to_points(s.scan));
  }
  return grid;
}

}  // namespace cairn::slam
