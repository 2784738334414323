// AgentPipeline: a robot whose laser falls silent (or never had one) goes on making poses and
// keyframes from odometry, with its landmarks, and picks the laser up again when it comes back.
#include <gtest/gtest.h>

#include "robot_agent/core/agent_pipeline.h"
#include "robot_agent/core/test_util.h"

namespace cairn::agent {
namespace {

struct Drive {
  std::vector<Keyframe> keyframes;
  std::vector<PosedScan> poses;
  SE2 T_world_local;
  std::vector<std::pair<StampNs, SE2>> truth;  ///< in the local frame
};

/// 12 s at 10 Hz along a gentle curve; the laser is silent from `silent_from_s` to `silent_to_s`;
/// a marker is seen every step.
Drive drive(AgentPipeline* agent, double silent_from_s, double silent_to_s) {
  const auto room = testing::make_room();
  const Eigen::Vector2d marker(2.5, 0.5);
  Drive d;
  SE2 pose(-3.0, -2.0, 0.2);
  d.T_world_local = pose;
  for (int i = 0; i <= 120; ++i) {
    const StampNs t = StampNs(i) * kNsPerSec / 10;
    const SE2 local = d.T_world_local.between(pose);
    d.truth.push_back({t, local});
    agent->add_odometry({t, local, 0, 0});
    if (ns_to_sec(t) < silent_from_s || ns_to_sec(t) >= silent_to_s) {
      agent->add_scan(testing::ray_cast(room, pose, t, 360, 0.01, unsigned(i)));
    }
    const Eigen::Vector2d q = pose.inverse() * marker;
    agent->add_landmark({LandmarkId(7), t, q.norm(), std::atan2(q.y(), q.x()), 0.02, 0.01});
    AgentOutputs out = agent->process();
    for (Keyframe& kf : out.keyframes) d.keyframes.push_back(std::move(kf));
    for (PosedScan& p : out.scans) d.poses.push_back(std::move(p));
    pose = pose * SE2(0.05, 0, 0.015);
  }
  for (Keyframe& kf : agent->process(true).keyframes) d.keyframes.push_back(std::move(kf));
  return d;
}

SE2 truth_at(const Drive& d, StampNs t) {
  for (const auto& [stamp, pose] : d.truth)
    if (stamp == t) return pose;
  ADD_FAILURE() << "no truth at " << t;
  return SE2();
}

TEST(AgentPipelineDeadReckoning, ASilentLaserStillGivesKeyframesFromOdometryUntilItComesBack) {
  AgentPipeline agent(RobotId(2));
  const Drive d = drive(&agent, 4.0, 9.0);
  const AgentStats s = agent.stats();
  EXPECT_EQ(s.laser_losses, 1);
  EXPECT_EQ(s.laser_recoveries, 1);
  EXPECT_FALSE(agent.laser_lost());
  // Every 0.1 s from the last scan (3.9 s) to the first scan back (9 s), made once the laser had
  // been silent for 1 s.
  EXPECT_EQ(s.dead_reckoned_poses, 50);
  ASSERT_GE(s.keyframes_without_scan, 3);
  int without_scan = 0, checked = 0;
  double worst_m = 0;
  for (size_t i = 0; i < d.keyframes.size(); ++i) {
    const Keyframe& kf = d.keyframes[i];
    EXPECT_EQ(kf.id.seq, int(i));
    worst_m = std::max(worst_m, (kf.T_local_base.translation() - truth_at(d, kf.stamp_ns).translation()).norm());
    if (i == 0) continue;
    if (!kf.scan.ranges_m.empty()) continue;
    ++without_scan;
    EXPECT_TRUE(kf.place_descriptor.empty());
    checked += !kf.landmarks.empty();
    if (d.keyframes[i - 1].scan.ranges_m.empty()) {
      // Between two odometry-only keyframes the edge is the odometry noise model's (along the way,
      // variance per metre driven; the lateral part also grows with the heading's) plus the
      // matched edges' floor.
      const double along_m = kf.T_prev_this.translation().norm();
      const DeadReckoningOptions o;
      const double floor_m2 = KeyframerOptions().edge_translation_floor_m2;
      EXPECT_NEAR(kf.edge_covariance(0, 0), o.translation_variance_m2_per_m * along_m + floor_m2,
                  0.1 * o.translation_variance_m2_per_m * along_m);
      EXPECT_GE(kf.edge_covariance(1, 1), o.translation_variance_m2_per_m * along_m);
      EXPECT_GE(kf.edge_covariance(2, 2), o.rotation_variance_rad2_per_m * along_m);
    }
  }
  EXPECT_EQ(without_scan, s.keyframes_without_scan);
  EXPECT_GT(checked, 0) << "the marker seen while the laser was silent reached the keyframes";
  EXPECT_LT(worst_m, 0.1) << "noise-free odometry: dead reckoning keeps the track";
  // Navigation got a pose (without beams) every 0.1 s through the silence.
  int no_beams = 0;
  for (const PosedScan& p : d.poses) no_beams += p.scan.ranges_m.empty();
  EXPECT_EQ(no_beams, s.dead_reckoned_poses);
}

TEST(AgentPipelineDeadReckoning, ARobotWithoutLaserSendsOdometryKeyframes) {
  AgentPipeline agent(RobotId(3));
  const Drive d = drive(&agent, 0.0, 1e9);
  EXPECT_TRUE(agent.laser_lost());
  ASSERT_GE(d.keyframes.size(), 5u);
  EXPECT_EQ(agent.stats().keyframes_without_scan, int(d.keyframes.size()));
  // The covariance of the pose grows along the way.
  EXPECT_GT(d.keyframes.back().covariance(1, 1), d.keyframes[1].covariance(1, 1));
}

TEST(AgentPipelineDeadReckoning, BeforeItsFirstScanALaserIsLostOnlyOnceTheArrivalTimeSaysSoToo) {
  // Live input: odometry stamps run seconds ahead of the first scan, which is only late.
  AgentPipeline agent(RobotId(3));
  agent.set_stamps_may_judge_laser(false);
  for (int i = 0; i <= 30; ++i) agent.add_odometry({StampNs(i) * kNsPerSec / 10, SE2(0.05 * i, 0, 0), 0, 0});
  EXPECT_TRUE(agent.process().scans.empty());
  EXPECT_FALSE(agent.laser_lost());
  agent.set_stamps_may_judge_laser(true);  // still no scan after the timeout on the wall clock
  EXPECT_FALSE(agent.process().scans.empty());
  EXPECT_TRUE(agent.laser_lost());
}

TEST(AgentPipelineDeadReckoning, OffItWaitsForTheLaser) {
  AgentOptions options;
  options.dead_reckon_without_laser = false;
  AgentPipeline agent(RobotId(3), options);
  const Drive d = drive(&agent, 0.0, 1e9);
  EXPECT_TRUE(d.keyframes.empty());
  EXPECT_EQ(agent.stats().dead_reckoned_poses, 0);
}

}  // namespace
}  // namespace cairn::agent
