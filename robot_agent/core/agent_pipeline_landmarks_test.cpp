// AgentPipeline: landmark observations are carried into keyframes, expressed from the keyframe's
// base frame, so that keyframe pose * observation lands on the marker.
#include <gtest/gtest.h>

#include <random>

#include "common/robot_markers.h"
#include "robot_agent/core/agent_pipeline.h"
#include "robot_agent/core/test_util.h"

namespace cairn::agent {
namespace {

TEST(AgentPipelineLandmarks, ObservationsReachKeyframesInTheirFrame) {
  const auto room = testing::make_room();
  const std::vector<Eigen::Vector2d> markers = {{1.0, -3.0}, {2.5, 0.5}, {-1.0, 0.0}};
  std::mt19937 rng(3);
  std::normal_distribution<double> n01(0.0, 1.0);
  AgentOptions options;
  options.max_pending_scans = 100000;
  AgentPipeline agent(RobotId(0), options);
  SE2 pose(-2.0, -2.0, 0.0);
  const SE2 T_world_local = pose;  // the local frame is where the robot started
  std::vector<Keyframe> keyframes;
  int sent = 0;
  for (int i = 0; i <= 60; ++i) {
    const StampNs t = StampNs(i) * kNsPerSec / 10;
    agent.add_odometry({t, T_world_local.between(pose), 0, 0});
    agent.add_scan(testing::ray_cast(room, pose, t, 360, 0.01, unsigned(i)));
    for (size_t m = 0; m < markers.size(); ++m) {
      const Eigen::Vector2d q = pose.inverse() * markers[m];
      if (q.norm() > 6.0) continue;
      // Seen a little after the scan (a camera at its own rate).
      agent.add_landmark({LandmarkId(int(m)), t + kNsPerSec / 40, q.norm() + 0.01 * n01(rng),
                          std::atan2(q.y(), q.x()) + 0.005 * n01(rng), 0.02, 0.01});
      ++sent;
    }
    for (Keyframe& kf : agent.process().keyframes) keyframes.push_back(std::move(kf));
    pose = pose * (i < 35 ? SE2(0.1, 0, 0) : SE2(0.05, 0, 0.12));
  }
  agent.add_landmark({LandmarkId(1), 0, std::nan(""), 0.0, 0.02, 0.01});  // invalid: counted, dropped
  for (Keyframe& kf : agent.process(true).keyframes) keyframes.push_back(std::move(kf));
  const AgentStats stats = agent.stats();
  EXPECT_EQ(stats.landmarks_received, sent + 1);
  EXPECT_EQ(stats.landmarks_invalid, 1);
  ASSERT_GE(keyframes.size(), 4u);
  int attached = 0;
  double worst = 0;
  for (const Keyframe& kf : keyframes) {
    for (const LandmarkObservation& o : kf.landmarks) {
      EXPECT_LE(o.stamp_ns, kf.stamp_ns);
      const Eigen::Vector2d truth_local = T_world_local.inverse() * markers[size_t(o.id.value)];
      worst = std::max(worst, (kf.T_local_base * o.point_m() - truth_local).norm());
      ++attached;
    }
  }
  EXPECT_EQ(attached, stats.landmarks_in_keyframes);
  EXPECT_GT(attached, sent / 2);  // only those after the last keyframe stay behind
  EXPECT_LT(worst, 0.15) << "marker position from keyframe pose + observation";
}

TEST(AgentPipelineLandmarks, ATeammatesMarkerBecomesASightingNotAnObject) {
  // Robot 1 (its marker's colour) stands at (2, 1); robot 0 drives past it with the camera on.
  const auto room = testing::make_room();
  const Eigen::Vector3d teammate(2.0, 1.0, 0.3);
  const RobotMarker marker = *robot_marker(RobotId(1));
  AgentOptions options;
  options.max_pending_scans = 100000;
  AgentPipeline agent(RobotId(0), options);
  SE2 pose(-2.0, -1.0, 0.3);
  const SE2 T_world_local = pose;
  std::vector<Keyframe> keyframes;
  int object_reports = 0;
  for (int i = 0; i <= 40; ++i) {
    const StampNs t = StampNs(i) * kNsPerSec / 10;
    agent.add_odometry({t, T_world_local.between(pose), 0, 0});
    agent.add_scan(testing::ray_cast(room, pose, t, 360, 0.01, unsigned(i)));
    if (i % 2 == 0) agent.add_rgbd(testing::render_rgbd(pose, teammate, 0.4, t, marker.color_rgb));
    AgentOutputs out = agent.process();
    object_reports += int(out.objects.size());
    for (Keyframe& kf : out.keyframes) keyframes.push_back(std::move(kf));
    pose = pose * SE2(0.06, 0, -0.008);
  }
  AgentOutputs out = agent.process(true);
  object_reports += int(out.objects.size());
  for (Keyframe& kf : out.keyframes) keyframes.push_back(std::move(kf));
  EXPECT_EQ(object_reports, 0) << "a teammate is not an object of interest";
  EXPECT_GT(agent.stats().robot_sightings, 5);
  int sightings = 0;
  double worst = 0;
  for (const Keyframe& kf : keyframes) {
    for (const LandmarkObservation& o : kf.landmarks) {
      ASSERT_EQ(o.id, robot_marker_landmark(RobotId(1)));
      const Eigen::Vector2d truth_local = T_world_local.inverse() * teammate.head<2>();
      worst = std::max(worst, (kf.T_local_base * o.point_m() - truth_local).norm());
      ++sightings;
    }
  }
  EXPECT_GT(sightings, 5);
  // The painted square is the marker's near face: its centre sits up to half its size closer.
  EXPECT_LT(worst, 0.25) << "teammate position from keyframe pose + sighting";
}

}  // namespace
}  // namespace cairn::agent
