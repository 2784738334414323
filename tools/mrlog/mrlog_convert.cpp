#include "tools/mrlog/mrlog_convert.h"

#include <algorithm>
#include <limits>
#include <random>
#include <set>

#include "common/errors.h"
#include "common/odometry_noise.h"
#include "sim/simulator.h"

namespace cairn::mrlog {
namespace {

/// Noisy range-bearing observation of `p_world` from `T_world_base`, or false when out of view.
bool observe(const SE2& T_world_base, const Eigen::Vector2d& p_world, const LandmarkSensorOptions& o,
             std::mt19937_64& rng, double* range_m, double* bearing_rad) {
  const Eigen::Vector2d q = T_world_base.inverse() * p_world;
  const double r = q.norm(), b = std::atan2(q.y(), q.x());
  if (r < o.min_range_m || r > o.max_range_m || std::abs(b) > 0.5 * o.fov_rad) return false;
  std::normal_distribution<double> n01(0.0, 1.0);
  *range_m = std::max(0.0, r + o.sigma_range_m * n01(rng));
  *bearing_rad = normalize_angle(b + o.sigma_bearing_rad * n01(rng));
  return true;
}

}  // namespace

MultiRobotLog record_world(const sim::WorldFile& wf, const WorldRecordOptions& options) {
  sim::SimOptions so = wf.sim;
  so.enable_camera = false;
  if (options.duration_s > 0) so.duration_s = options.duration_s;
  sim::Simulator sim(wf.world, so);
  const std::vector<RobotId> all = sim.robot_ids();
  std::set<RobotId> wanted;
  for (int id : options.robots) {
    if (std::find(all.begin(), all.end(), RobotId(id)) == all.end()) {
      throw InputError("robot " + std::to_string(id) + " is not in world '" + wf.world.name + "'");
    }
    wanted.insert(RobotId(id));
  }
  if (wanted.empty()) wanted.insert(all.begin(), all.end());
  MultiRobotLog log;
  for (const sim::WorldObject& obj : wf.world.objects) log.markers[LandmarkId(obj.id)] = obj.center_m.head<2>();
  std::mt19937_64 rng(options.landmarks.seed);
  const LandmarkSensorOptions& lo = options.landmarks;
  const StampNs landmark_period_ns = lo.rate_hz > 0 ? sec_to_ns(1.0 / lo.rate_hz) : 0;
  StampNs next_landmark_ns = 0;
  while (!sim.done()) {
    const sim::SimStep step = sim.step();
    for (const auto& [robot, odom] : step.odometry) {
      if (wanted.count(robot)) log.robot_data(robot).odometry.push_back(odom);
    }
    for (const auto& [robot, scan] : step.scans) {
      if (!wanted.count(robot)) continue;
      RobotLogData& r = log.robot_data(robot);
      r.scans.push_back(scan);
      if (options.featureless)
        r.scans.back().ranges_m.assign(scan.ranges_m.size(), std::numeric_limits<float>::infinity());
      r.truth.push_back({step.stamp_ns, sim.ground_truth(robot).back().pose});
    }
    if (landmark_period_ns <= 0 || step.stamp_ns < next_landmark_ns) continue;
    next_landmark_ns += landmark_period_ns;
    for (RobotId robot : wanted) {
      const SE2 T = sim.ground_truth(robot).back().pose;
      for (const sim::WorldObject& obj : wf.world.objects) {
        const Eigen::Vector2d p = obj.center_m.head<2>();
        double range = 0, bearing = 0;
        if (!observe(T, p, lo, rng, &range, &bearing)) continue;
        const double d = (p - T.translation()).norm();
        const double half_size = 0.5 * obj.size_m.head<2>().maxCoeff();
        const auto hit = wf.world.floor_plan.cast_ray(T.translation(), std::atan2(p.y() - T.y(), p.x() - T.x()), d);
        if (hit.hit && hit.range_m < d - half_size - 0.05) continue;  // behind a wall
        log.robot_data(robot).landmarks.push_back(LandmarkObservation{LandmarkId(obj.id), step.stamp_ns, range, bearing,
                                                                      lo.sigma_range_m, lo.sigma_bearing_rad});
      }
    }
  }
  return log;
}

namespace {

/// Appends scans [begin, end) of `log` as `robot`; odometry re-zeroed at `begin`.
void add_segment(const CarmenLog& log, bool corrected, size_t begin, size_t end, RobotId robot,
                 const std::vector<SE2>& noisy_odometry, MultiRobotLog* out) {
  RobotLogData& r = out->robot_data(robot);
  const std::vector<CarmenScan>& s = log.scans;
  const SE2 odom0_inv = (corrected ? noisy_odometry[begin] : s[begin].T_odom_laser).inverse();
  for (size_t i = begin; i < end; ++i) {
    const SE2 odom = corrected ? noisy_odometry[i] : s[i].T_odom_laser;
    r.odometry.push_back({s[i].stamp_ns, odom0_inv * odom, 0, 0});
    r.scans.push_back(s[i].scan);
    if (corrected) r.truth.push_back({s[i].stamp_ns, s[i].T_world_laser});
  }
}

/// Virtual markers every `spacing` metres along the reference path, `offset` to its left.
std::vector<Eigen::Vector2d> virtual_markers(const std::vector<CarmenScan>& scans, double spacing_m, double offset_m) {
  std::vector<Eigen::Vector2d> out;
  double travelled = spacing_m;  // a marker near the start too
  for (size_t i = 0; i < scans.size(); ++i) {
    if (i > 0) travelled += (scans[i].T_world_laser.translation() - scans[i - 1].T_world_laser.translation()).norm();
    if (travelled < spacing_m) continue;
    const Eigen::Vector2d p = scans[i].T_world_laser * Eigen::Vector2d(0.0, offset_m);
    bool near = false;  // revisited places keep one marker
    for (const Eigen::Vector2d& q : out) near = near || (q - p).norm() < 0.5 * spacing_m;
    if (!near) out.push_back(p);
    travelled = 0;
  }
  return out;
}

}  // namespace

MultiRobotLog convert_carmen(const std::vector<CarmenLog>& logs, const std::vector<bool>& corrected,
                             const CarmenConvertOptions& o) {
  if (logs.empty() || logs.size() != corrected.size()) throw InputError("convert_carmen: no logs");
  if (o.split < 1) throw InputError("--split must be >= 1");
  if (logs.size() > 1 && o.split > 1) throw InputError("--split needs exactly one input log");
  if (o.virtual_marker_spacing_m > 0 && (logs.size() != 1 || !corrected[0])) {
    throw InputError("virtual markers need one GMapping-corrected log (its poses are the reference)");
  }
  MultiRobotLog out;
  for (size_t k = 0; k < logs.size(); ++k) {
    if (logs[k].scans.empty()) throw InputError("input log " + std::to_string(k) + " holds no laser scans");
    std::vector<SE2> noisy;
    if (corrected[k]) {
      std::vector<SE2> reference;
      for (const CarmenScan& s : logs[k].scans) reference.push_back(s.T_world_laser);
      OdometryNoiseOptions no;
      no.seed = o.odometry_noise_seed + uint32_t(k);
      noisy = add_odometry_noise(reference, no);
    }
    const int parts = logs.size() == 1 ? o.split : 1;
    const size_t n = logs[k].scans.size();
    for (int p = 0; p < parts; ++p) {
      const RobotId robot(logs.size() == 1 ? p : int(k));
      add_segment(logs[k], corrected[k], n * size_t(p) / size_t(parts), n * size_t(p + 1) / size_t(parts), robot, noisy,
                  &out);
    }
  }
  if (o.virtual_marker_spacing_m > 0) {
    const std::vector<Eigen::Vector2d> markers =
        virtual_markers(logs[0].scans, o.virtual_marker_spacing_m, o.virtual_marker_offset_m);
    for (size_t m = 0; m < markers.size(); ++m) out.markers[LandmarkId(int(m))] = markers[m];
    std::mt19937_64 rng(o.landmarks.seed);
    const StampNs period_ns = o.landmarks.rate_hz > 0 ? sec_to_ns(1.0 / o.landmarks.rate_hz) : 0;
    for (auto& [robot, r] : out.robots) {
      StampNs next_ns = std::numeric_limits<StampNs>::min();
      for (const StampedPose& t : r.truth) {
        if (t.stamp_ns < next_ns) continue;
        if (period_ns > 0) next_ns = t.stamp_ns + period_ns;
        for (const auto& [id, p] : out.markers) {
          double range = 0, bearing = 0;
          if (!observe(t.pose, p, o.landmarks, rng, &range, &bearing)) continue;
          r.landmarks.push_back(
              {id, t.stamp_ns, range, bearing, o.landmarks.sigma_range_m, o.landmarks.sigma_bearing_rad});
        }
      }
    }
  }
  return out;
}

}  // namespace cairn::mrlog
