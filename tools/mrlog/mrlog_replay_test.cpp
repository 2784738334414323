// End to end without DDS: a simulated world recorded into the multi-robot text log (markers =
// the world's numbered signs), written and read back, each robot replayed through its own
// AgentPipeline (odometry, scans and landmark observations, as cairn_agent --log does), and the
// keyframes merged by a MultiRobotMapper that knows no robot's start. Checks the link, the markers'
// global positions and the trajectories against the log's reference.
#include <gtest/gtest.h>

#include <sstream>

#include "base_station/core/multi_robot_mapper.h"
#include "robot_agent/core/agent_pipeline.h"
#include "tools/mrlog/mrlog_convert.h"

namespace cairn::mrlog {
namespace {

const std::string kWorld = std::string(CAIRN_SOURCE_DIR) + "/tools/mrlog/worlds/corridor_markers.yaml";

std::vector<Keyframe> run_agent(const RobotLogData& r) {
  agent::AgentOptions options;
  options.max_pending_scans = 100000;
  agent::AgentPipeline agent(r.robot, options);
  std::vector<Keyframe> out;
  size_t o = 0, l = 0;
  for (const LaserScan& s : r.scans) {
    for (; o < r.odometry.size() && r.odometry[o].stamp_ns <= s.stamp_ns; ++o) agent.add_odometry(r.odometry[o]);
    agent.add_scan(s);
    for (; l < r.landmarks.size() && r.landmarks[l].stamp_ns <= s.stamp_ns; ++l) agent.add_landmark(r.landmarks[l]);
    for (Keyframe& kf : agent.process().keyframes) out.push_back(std::move(kf));
  }
  for (Keyframe& kf : agent.process(true).keyframes) out.push_back(std::move(kf));
  return out;
}

struct Result {
  bool linked = false;
  double marker_max_m = 0, marker_rms_m = 0, ate_max_m = 0;
  int markers = 0;
};

Result replay(const MultiRobotLog& log, const base::MapperOptions& options) {
  std::map<RobotId, std::vector<Keyframe>> keyframes;
  for (const auto& [id, r] : log.robots) keyframes[id] = run_agent(r);
  base::MultiRobotMapper mapper(options);
  for (size_t i = 0;; ++i) {
    bool any = false;
    for (const auto& [id, list] : keyframes) {
      if (i < list.size()) mapper.add_keyframe(list[i]), any = true;
    }
    if (i % 5 == 4 || !any) mapper.optimize();
    if (!any) break;
  }
  Result res;
  res.linked = mapper.linked(RobotId(1));
  const SE2 T_global_world = log.robot(RobotId(0))->truth.front().pose.inverse();
  double sum2 = 0;
  for (const auto& [id, p] : mapper.landmarks()) {
    const double e = (p - T_global_world * log.markers.at(id)).norm();
    res.marker_max_m = std::max(res.marker_max_m, e);
    sum2 += e * e;
    ++res.markers;
  }
  res.marker_rms_m = res.markers ? std::sqrt(sum2 / res.markers) : 0;
  for (const auto& [id, list] : keyframes) {
    for (const StampedPose& p : mapper.global_trajectory(id)) {
      const auto truth = interpolate_pose(log.robot(id)->truth, p.stamp_ns);
      if (truth)
        res.ate_max_m =
            std::max(res.ate_max_m, (p.pose.translation() - (T_global_world * *truth).translation()).norm());
    }
  }
  return res;
}

TEST(MrlogReplay, CorridorRobotsLinkAndMarkersAreRecovered) {
  std::stringstream ss;
  write_multirobot_log(ss, record_world(sim::load_world_file(kWorld), {}));
  const MultiRobotLog log = parse_multirobot_log(ss, "corridor.mrlog");
  const Result with = replay(log, {});
  base::MapperOptions off;
  off.landmarks.enabled = false;
  const Result without = replay(log, off);
  std::printf(
      "[mrlog replay] with markers: linked %d, %d markers rms %.3f max %.3f m, trajectory max error %.3f m; "
      "scans only: linked %d, trajectory max error %.3f m\n",
      with.linked, with.markers, with.marker_rms_m, with.marker_max_m, with.ate_max_m, without.linked,
      without.ate_max_m);
  ASSERT_TRUE(with.linked);
  EXPECT_EQ(with.markers, 6);
  EXPECT_LT(with.marker_max_m, 0.15);
  // The markers must not make the map worse than the scans alone (noise margin 5 cm).
  EXPECT_LT(with.ate_max_m, without.ate_max_m + 0.05);
}

}  // namespace
}  // namespace cairn::mrlog
