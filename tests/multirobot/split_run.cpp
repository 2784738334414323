#include "tests/multirobot/split_run.h"

#include <chrono>
#include <unordered_map>

#include "common/odometry_noise.h"
#include "robot_agent/core/agent_pipeline.h"

namespace cairn::multirobot {
namespace {

// Ranges rounded to centimetres: identical scans from two logs (different print precision) agree.
std::string range_key(const LaserScan& s) {
  std::string key;
  for (float r : s.ranges_m) key += std::to_string(std::isfinite(r) ? std::lround(r * 100.f) : -1) + ",";
  return key;
}

}  // namespace

ReplayLog replay_from_raw(const CarmenLog& raw, const CarmenLog& corrected, int* matched) {
  ReplayLog out;
  std::unordered_map<std::string, SE2> corrected_by_key;
  for (const CarmenScan& s : corrected.scans) corrected_by_key.emplace(range_key(s.scan), s.T_world_laser);
  std::vector<int> twin(raw.scans.size(), -1);
  std::vector<SE2> ref(raw.scans.size());
  *matched = 0;
  for (size_t i = 0; i < raw.scans.size(); ++i) {
    auto it = corrected_by_key.find(range_key(raw.scans[i].scan));
    if (it == corrected_by_key.end()) continue;
    ref[i] = it->second;
    twin[i] = int(i);
    ++*matched;
  }
  if (*matched == 0) return out;
  // Between two matched scans the reference is carried by raw odometry from the previous one, and
  // the odometry's disagreement with the next one is spread over the gap: yaw by the odometry's
  // turning, position by its travel. (Carried from the nearest matched scan alone, the reference
  // of in-place turns was up to 16 deg off: inter-robot closures that agree with a full-log SLAM
  // run within 0.75 deg scored 7-16 deg "off" at keyframes 1-2 scans from a matched one.)
  std::vector<int> prev(raw.scans.size(), -1), next(raw.scans.size(), -1);
  for (size_t i = 0, last = size_t(-1); i < raw.scans.size(); ++i) {
    if (twin[i] >= 0) last = i;
    prev[i] = last == size_t(-1) ? -1 : int(last);
  }
  for (size_t k = raw.scans.size(), last = size_t(-1); k-- > 0;) {
    if (twin[k] >= 0) last = k;
    next[k] = last == size_t(-1) ? -1 : int(last);
  }
  const auto odom = [&](size_t i) { return raw.scans[i].T_odom_laser; };
  for (size_t i = 0; i < raw.scans.size(); ++i) {
    out.scans.push_back(raw.scans[i]);
    const int p = prev[i], n = next[i];
    out.measured_reference.push_back(p < 0 ? n : n < 0 ? p : int(i) - p <= n - int(i) ? p : n);
    out.odometry.push_back(odom(i));
    if (p < 0 || n < 0 || p == n) {  // before the first or after the last matched scan, or matched
      const int j = p >= 0 ? p : n;
      out.reference.push_back(ref[size_t(j)] * odom(size_t(j)).between(odom(i)));
      continue;
    }
    // Odometry turning and travel from p to i, and from p to n.
    double turn_i = 0, turn_n = 0, travel_i = 0, travel_n = 0;
    for (int k = p; k < n; ++k) {
      const SE2 step = odom(size_t(k)).between(odom(size_t(k + 1)));
      turn_n += std::abs(step.yaw());
      travel_n += step.translation().norm();
      if (k < int(i)) turn_i += std::abs(step.yaw()), travel_i += step.translation().norm();
    }
    const double by_index = double(int(i) - p) / double(n - p);
    const double f_yaw = turn_n > 1e-6 ? turn_i / turn_n : by_index;
    const double f_xy = travel_n > 1e-6 ? travel_i / travel_n : by_index;
    const SE2 carried = ref[size_t(p)] * odom(size_t(p)).between(odom(i));
    const SE2 carried_n = ref[size_t(p)] * odom(size_t(p)).between(odom(size_t(n)));
    // The correction that moves the carried pose at n onto n's reference: a turn about p's
    // reference position (f_yaw of it at i), then a shift (f_xy of it at i).
    const double dyaw = normalize_angle(ref[size_t(n)].yaw() - carried_n.yaw());
    const Eigen::Vector2d pivot = ref[size_t(p)].translation();
    const Eigen::Vector2d dxy = ref[size_t(n)].translation() - (pivot + Eigen::Rotation2Dd(dyaw).toRotationMatrix() *
                                                                            (carried_n.translation() - pivot));
    const Eigen::Vector2d t =
        pivot + Eigen::Rotation2Dd(f_yaw * dyaw).toRotationMatrix() * (carried.translation() - pivot) + f_xy * dxy;
    out.reference.emplace_back(t.x(), t.y(), carried.yaw() + f_yaw * dyaw);
  }
  return out;
}

ReplayLog replay_from_corrected(const CarmenLog& corrected, uint32_t seed) {
  ReplayLog out;
  for (const CarmenScan& s : corrected.scans) {
    out.scans.push_back(s);
    out.reference.push_back(s.T_world_laser);
    out.measured_reference.push_back(int(out.scans.size()) - 1);
  }
  OdometryNoiseOptions noise;  // 10 % of distance, 3 deg per metre
  noise.seed = seed;
  out.odometry = add_odometry_noise(out.reference, noise);
  return out;
}

RobotRun run_agent(const ReplayLog& log, size_t begin, size_t end, RobotId robot) {
  agent::AgentOptions options;
  options.enable_objects = false;
  agent::AgentPipeline pipeline(robot, options);
  RobotRun run;
  const SE2 T_zero = log.odometry[begin].inverse();
  std::unordered_map<StampNs, size_t> scan_of;
  auto collect = [&run](agent::AgentOutputs out) {
    for (Keyframe& kf : out.keyframes) run.keyframes.push_back(std::move(kf));
    if (out.keyframe_poses) run.keyframe_poses.emplace_back(run.keyframes.size(), std::move(*out.keyframe_poses));
  };
  for (size_t i = begin; i < end; ++i) {
    const CarmenScan& s = log.scans[i];
    scan_of[s.stamp_ns] = i;
    pipeline.add_odometry({s.stamp_ns, T_zero * log.odometry[i], 0.0, 0.0});
    pipeline.add_scan(s.scan);
    collect(pipeline.process());
  }
  collect(pipeline.process(true));
  for (const Keyframe& kf : run.keyframes) {
    auto it = scan_of.find(kf.stamp_ns);
    run.reference.push_back(it != scan_of.end() ? log.reference[it->second] : SE2(NAN, NAN, NAN));
    const int m =
        it != scan_of.end() && it->second < log.measured_reference.size() ? log.measured_reference[it->second] : -1;
    if (m < int(begin) || m >= int(end)) {
      run.closure_reference.push_back(run.reference.back());
      continue;
    }
    const SE2 T_measured_kf = pipeline.pose_at(log.scans[size_t(m)].stamp_ns).between(pipeline.pose_at(kf.stamp_ns));
    run.closure_reference.push_back(log.reference[size_t(m)] * T_measured_kf);
  }
  return run;
}

std::vector<RobotRun> run_split(const ReplayLog& log, int robots) {
  std::vector<RobotRun> runs;
  const size_t n = log.scans.size();
  for (int k = 0; k < robots; ++k) runs.push_back(run_agent(log, n * k / robots, n * (k + 1) / robots, RobotId(k)));
  return runs;
}

MergeStats merge(const std::vector<RobotRun>& runs, base::MultiRobotMapper* mapper, int optimize_every) {
  MergeStats stats;
  mapper->set_robot_start(RobotId(0), SE2());
  size_t longest = 0;
  for (const RobotRun& r : runs) longest = std::max(longest, r.keyframes.size());
  auto optimize = [&] {
    const auto t0 = std::chrono::steady_clock::now();
    base::OptimizeResult result = mapper->optimize();
    for (base::LinkEvent& e : result.link_events) stats.link_events.push_back(std::move(e));
    ++stats.optimizations;
    stats.max_optimize_s =
        std::max(stats.max_optimize_s, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  };
  int added = 0;
  std::vector<size_t> next_poses(runs.size(), 0);
  for (size_t step = 0; step < longest; ++step) {
    for (size_t k = 0; k < runs.size(); ++k) {
      const RobotRun& r = runs[k];
      // Same progress fraction for every robot.
      const size_t from = r.keyframes.size() * step / longest, to = r.keyframes.size() * (step + 1) / longest;
      for (size_t i = from; i < to; ++i) {
        mapper->add_keyframe(r.keyframes[i]);
        // The agent's loop-closed poses, once the base has the keyframes it had sent with them.
        for (size_t& u = next_poses[k]; u < r.keyframe_poses.size() && r.keyframe_poses[u].first <= i + 1; ++u) {
          mapper->add_keyframe_poses(r.keyframe_poses[u].second);
        }
        if (++added % optimize_every == 0) optimize();
      }
    }
  }
  optimize();
  return stats;
}

double merged_ate_m(const std::vector<RobotRun>& runs, const base::MultiRobotMapper& mapper, int* matched) {
  std::vector<Eigen::Vector2d> est, ref;
  for (const RobotRun& r : runs) {
    for (size_t i = 0; i < r.keyframes.size(); ++i) {
      const auto p = mapper.global_pose(r.keyframes[i].id);
      if (!p || !r.reference[i].vector().allFinite()) continue;
      est.push_back(p->translation());
      ref.push_back(r.reference[i].translation());
    }
  }
  *matched = int(est.size());
  if (est.size() < 2) return 1e9;
  const SE2 T = align_points_2d(est, ref);
  double sum = 0;
  for (size_t i = 0; i < est.size(); ++i) sum += (T * est[i] - ref[i]).squaredNorm();
  return std::sqrt(sum / double(est.size()));
}

ClosureError closure_error(const base::LoopClosure& c, const std::vector<RobotRun>& runs) {
  auto ref = [&](KeyframeId id) {
    const RobotRun& r = runs.at(size_t(id.robot.value));
    return r.closure_reference.at(size_t(id.seq));
  };
  const SE2 truth = ref(c.a).between(ref(c.b));
  const SE2 e = truth.between(c.T_a_b);
  return {e.translation().norm(), std::abs(e.yaw())};
}

}  // namespace cairn::multirobot
