#include "robot_agent/core/agent_pipeline.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <limits>

#include "common/carmen_log.h"
#include "common/odometry_noise.h"
#include "robot_agent/core/test_util.h"

namespace cairn::agent {
namespace {

constexpr double kDeg = M_PI / 180.0;

struct Sequence {
  std::vector<OdometryReading> odometry;
  std::vector<LaserScan> scans;
  std::vector<RgbdFrame> frames;
  std::vector<SE2> truth;  ///< at each scan
};

// Drives forward 4 m then turns left 90 deg and drives 2 m: scans at 10 Hz, odometry at 20 Hz
// (3 % scale error), RGB-D at 5 Hz looking at a red object ahead.
Sequence make_sequence() {
  const auto room = testing::make_room();
  Sequence s;
  SE2 pose(-2.0, -2.0, 0.0), odom;
  std::vector<SE2> steps;
  for (int i = 0; i < 40; ++i) steps.push_back(SE2(0.1, 0, 0));
  for (int i = 0; i < 9; ++i) steps.push_back(SE2(0, 0, 10 * kDeg));
  for (int i = 0; i < 20; ++i) steps.push_back(SE2(0.1, 0, 0));
  const StampNs dt = kNsPerSec / 10;
  for (size_t i = 0; i <= steps.size(); ++i) {
    const StampNs t = StampNs(i) * dt;
    s.truth.push_back(pose);
    s.scans.push_back(testing::ray_cast(room, pose, t, 360, 0.01, unsigned(i)));
    s.odometry.push_back({t, odom, 0.0, 0.0});
    if (i % 2 == 0) s.frames.push_back(testing::render_rgbd(pose, {2.8, -2.0, 0.4}, 0.3, t + dt / 4));
    if (i == steps.size()) break;
    const SE2 half = SE2::from_vector(0.5 * steps[i].vector());
    const SE2 odom_half(1.03 * half.x(), half.y(), half.yaw());
    odom = odom * odom_half;
    s.odometry.push_back({t + dt / 2, odom, 0.0, 0.0});
    odom = odom * odom_half;
    pose = pose * steps[i];
  }
  return s;
}

AgentOptions test_options() {
  AgentOptions o;
  o.max_pending_scans = 100000;
  return o;
}

struct Event {
  int topic;  // 0 odometry, 1 scan, 2 rgbd
  size_t index;
};

AgentOutputs run(const Sequence& s, const std::vector<Event>& events, int process_every, AgentPipeline* agent) {
  AgentOutputs all;
  auto append = [&all](AgentOutputs o) {
    for (auto& k : o.keyframes) all.keyframes.push_back(std::move(k));
    for (auto& r : o.objects) all.objects.push_back(std::move(r));
  };
  for (size_t i = 0; i < events.size(); ++i) {
    const Event& e = events[i];
    if (e.topic == 0) agent->add_odometry(s.odometry[e.index]);
    if (e.topic == 1) agent->add_scan(s.scans[e.index]);
    if (e.topic == 2) agent->add_rgbd(s.frames[e.index]);
    if (int(i) % process_every == 0) append(agent->process());
  }
  append(agent->process(true));
  return all;
}

std::vector<Event> topic_major(const Sequence& s, const std::vector<int>& order) {
  std::vector<Event> events;
  for (int topic : order) {
    const size_t n = topic == 0 ? s.odometry.size() : topic == 1 ? s.scans.size() : s.frames.size();
    for (size_t i = 0; i < n; ++i) events.push_back({topic, i});
  }
  return events;
}

/// In stamp order, but odometry arrives `odometry_ahead_ns` ahead of the other topics.
std::vector<Event> chronological(const Sequence& s, StampNs odometry_ahead_ns = 0) {
  std::vector<std::pair<StampNs, Event>> ev;
  for (size_t i = 0; i < s.odometry.size(); ++i) ev.push_back({s.odometry[i].stamp_ns - odometry_ahead_ns, {0, i}});
  for (size_t i = 0; i < s.scans.size(); ++i) ev.push_back({s.scans[i].stamp_ns, {1, i}});
  for (size_t i = 0; i < s.frames.size(); ++i) ev.push_back({s.frames[i].stamp_ns, {2, i}});
  std::stable_sort(ev.begin(), ev.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<Event> out;
  for (const auto& e : ev) out.push_back(e.second);
  return out;
}

void expect_identical(const AgentOutputs& a, const AgentOutputs& b) {
  ASSERT_EQ(a.keyframes.size(), b.keyframes.size());
  for (size_t i = 0; i < a.keyframes.size(); ++i) {
    EXPECT_EQ(a.keyframes[i].id, b.keyframes[i].id);
    EXPECT_EQ(a.keyframes[i].stamp_ns, b.keyframes[i].stamp_ns);
    EXPECT_EQ(a.keyframes[i].T_local_base.vector(), b.keyframes[i].T_local_base.vector());
  }
  ASSERT_EQ(a.objects.size(), b.objects.size());
  for (size_t i = 0; i < a.objects.size(); ++i) {
    EXPECT_EQ(a.objects[i].id, b.objects[i].id);
    EXPECT_EQ(a.objects[i].anchor_seq, b.objects[i].anchor_seq);
    EXPECT_EQ(a.objects[i].stamp_ns, b.objects[i].stamp_ns);
    EXPECT_TRUE(a.objects[i].T_anchor_object.isApprox(b.objects[i].T_anchor_object, 0.0));
    EXPECT_EQ(a.objects[i].cloud.size(), b.objects[i].cloud.size());
  }
}

TEST(AgentPipeline, DeterministicUnderInterleavings) {
  const Sequence s = make_sequence();
  // Any interleaving: a laser that stays silent while odometry runs on is a laser lost (dead
  // reckoning), so for topics a whole sequence apart it is off here; the next test holds it on.
  AgentOptions any_order = test_options();
  any_order.dead_reckon_without_laser = false;
  AgentPipeline a(RobotId(1), test_options()), b(RobotId(1), any_order), c(RobotId(1), any_order);
  const AgentOutputs out_a = run(s, chronological(s), 1, &a);
  const AgentOutputs out_b = run(s, topic_major(s, {1, 2, 0}), 7, &b);
  const AgentOutputs out_c = run(s, topic_major(s, {0, 2, 1}), 3, &c);
  ASSERT_GE(out_a.keyframes.size(), 8u);
  ASSERT_GE(out_a.objects.size(), 1u);
  expect_identical(out_a, out_b);
  expect_identical(out_a, out_c);
  EXPECT_EQ(a.trajectory().size(), b.trajectory().size());
  // Accuracy against the truth (local frame = start pose).
  const SE2 end = s.truth.front() * a.pose_at(s.scans.back().stamp_ns);
  EXPECT_LT((end.translation() - s.truth.back().translation()).norm(), 0.05);
  // The object is at (2.8, -2.0, 0.4) in the world.
  const ObjectReport& obj = out_a.objects.back();
  EXPECT_EQ(obj.class_name, "victim");
  const Keyframe& anchor = out_a.keyframes[size_t(obj.anchor_seq)];
  const Eigen::Vector3d p_world =
      (s.truth.front() * anchor.T_local_base).to_isometry3() * obj.T_anchor_object.translation();
  EXPECT_LT((p_world - Eigen::Vector3d(2.8, -2.0, 0.4)).norm(), 0.05);
  const AgentStats st = a.stats();
  EXPECT_EQ(st.scans_received, int(s.scans.size()));
  EXPECT_EQ(st.scans_matched + st.scans_motion_filtered, int(s.scans.size()));
  EXPECT_EQ(st.object_tracks, 1);
}

TEST(AgentPipeline, DeterministicWhileOdometryRunsAheadByLessThanTheLaserTimeout) {
  const Sequence s = make_sequence();
  AgentPipeline a(RobotId(1), test_options()), b(RobotId(1), test_options());
  const AgentOutputs out_a = run(s, chronological(s), 1, &a);
  const AgentOutputs out_b = run(s, chronological(s, sec_to_ns(0.8)), 1, &b);  // the timeout is 1 s
  expect_identical(out_a, out_b);
  EXPECT_EQ(b.stats().laser_losses, 0);
  AgentPipeline c(RobotId(1), test_options());
  run(s, chronological(s, sec_to_ns(1.5)), 1, &c);  // this late, the laser counts as lost
  EXPECT_GE(c.stats().laser_losses, 1);
}

TEST(AgentPipeline, KeyframesCarryTheSalientSpotsTheCameraSawAtTheirPlaceOnTheFloor) {
  const Sequence s = make_sequence();
  AgentPipeline agent(RobotId(1), test_options());
  const AgentOutputs out = run(s, chronological(s), 1, &agent);
  int spots = 0;
  for (const Keyframe& kf : out.keyframes) {
    for (const SalientPoint& p : kf.salient) {
      ++spots;
      // The red object (0.3 m across, at (2.8, -2.0) in the world) is the only colourful thing seen:
      // its front face, pooled in 0.25 m cells.
      const Eigen::Vector2d world = (s.truth.front() * kf.T_local_base) * Eigen::Vector2d(p.x_m, p.y_m);
      EXPECT_LT((world - Eigen::Vector2d(2.8, -2.0)).norm(), 0.45) << world.transpose();
      EXPECT_GT(p.weight, 0.0f);
      EXPECT_LE(p.weight, 1.0f);
    }
  }
  EXPECT_GT(spots, 0);
  EXPECT_EQ(agent.stats().salient_points, spots);
  AgentOptions off = test_options();
  off.enable_saliency_map = false;
  AgentPipeline blind(RobotId(1), off);
  for (const Keyframe& kf : run(s, chronological(s), 1, &blind).keyframes) EXPECT_TRUE(kf.salient.empty());
}

TEST(AgentPipeline, BeamsOnATeammatesReflectorStayOutOfSlamAndKeyframes) {
  const auto room = testing::make_room();
  LaserScan scan = testing::ray_cast(room, SE2(), 0);
  scan.intensities.assign(scan.ranges_m.size(), 0.3f);
  for (size_t i = 100; i < 110; ++i) scan.ranges_m[i] = 1.0f, scan.intensities[i] = 1.0f;  // a teammate 1 m off
  int dropped = 0;
  const LaserScan slam = without_teammates(scan, 0.9f, &dropped);
  EXPECT_EQ(dropped, 10);
  EXPECT_TRUE(std::isinf(slam.ranges_m[105]));
  EXPECT_EQ(slam.ranges_m[50], scan.ranges_m[50]);
  EXPECT_EQ(without_teammates(scan, 0.f, &dropped).ranges_m, scan.ranges_m) << "off";
  LaserScan no_channel = scan;
  no_channel.intensities.clear();
  EXPECT_EQ(without_teammates(no_channel, 0.9f, &dropped).ranges_m, scan.ranges_m) << "a laser without intensities";
  // Through the pipeline: the keyframe's scan has no teammate, navigation's scan still has it.
  AgentPipeline agent(RobotId(0), test_options());
  agent.add_odometry({0, SE2(), 0, 0});
  agent.add_scan(scan);
  const AgentOutputs out = agent.process(true);
  ASSERT_EQ(out.keyframes.size(), 1u);
  EXPECT_TRUE(std::isinf(out.keyframes[0].scan.ranges_m[105]));
  ASSERT_EQ(out.scans.size(), 1u);
  EXPECT_FLOAT_EQ(out.scans[0].scan.ranges_m[105], 1.0f);
  EXPECT_EQ(agent.stats().teammate_beams, 10);
}

TEST(AgentPipeline, KeyframePosesCarryTheAgentsLoopClosuresOnARealLog) {
  // The Intel lab with 10 % / 3 deg per metre odometry noise (issue 3's protocol): the keyframes
  // carry the front end's poses; the agent's loop closing straightens them, and what it sends as
  // KeyframePoses must be that straightened map, for every keyframe, at most every 5 s of log time.
  const std::string path = std::string(CAIRN_SHARED_DATA_DIR) + "/carmen/intel/intel.gfs.log";
  if (!std::ifstream(path)) GTEST_SKIP() << "data absent: " << path;
  const CarmenLog log = read_carmen_log(path);
  std::vector<SE2> reference;
  Trajectory reference_trajectory;
  for (const CarmenScan& s : log.scans)
    reference.push_back(s.T_world_laser), reference_trajectory.push_back({s.stamp_ns, s.T_world_laser});
  const std::vector<SE2> odometry = add_odometry_noise(reference, OdometryNoiseOptions{});
  AgentOptions options;
  options.enable_objects = false;
  AgentPipeline agent(RobotId(0), options);
  std::vector<Keyframe> keyframes;
  std::vector<KeyframePoses> updates;
  auto collect = [&](AgentOutputs out) {
    for (Keyframe& kf : out.keyframes) keyframes.push_back(std::move(kf));
    if (out.keyframe_poses) updates.push_back(std::move(*out.keyframe_poses));
  };
  for (size_t i = 0; i < log.scans.size(); ++i) {
    agent.add_odometry({log.scans[i].stamp_ns, odometry[i], 0.0, 0.0});
    agent.add_scan(log.scans[i].scan);
    collect(agent.process());
  }
  collect(agent.process(true));
  ASSERT_GT(keyframes.size(), 100u);
  ASSERT_GE(updates.size(), 3u);
  for (size_t u = 1; u + 1 < updates.size(); ++u)
    EXPECT_GE(updates[u].stamp_ns - updates[u - 1].stamp_ns, 5 * kNsPerSec);
  const KeyframePoses& last = updates.back();
  ASSERT_EQ(last.poses.size(), keyframes.size()) << "the final estimate covers every keyframe";
  Trajectory front_end, loop_closed;
  for (size_t i = 0; i < keyframes.size(); ++i) {
    ASSERT_EQ(last.poses[i].seq, keyframes[i].id.seq);
    front_end.push_back({keyframes[i].stamp_ns, keyframes[i].T_local_base});
    loop_closed.push_back({keyframes[i].stamp_ns, last.poses[i].T_local_base});
  }
  EXPECT_LT((last.poses[0].T_local_base.translation() - keyframes[0].T_local_base.translation()).norm(), 1e-3)
      << "the agent's loop closing keeps its start";
  TrajectoryErrorOptions exact;  // keyframe stamps are scan stamps: no interpolation across log gaps
  exact.max_gap_ns = std::numeric_limits<StampNs>::max();
  const auto front_end_error = trajectory_error(front_end, reference_trajectory, exact);
  const auto loop_closed_error = trajectory_error(loop_closed, reference_trajectory, exact);
  ASSERT_TRUE(front_end_error && loop_closed_error);
  const double front_end_m = front_end_error->ate_rmse_m, loop_closed_m = loop_closed_error->ate_rmse_m;
  std::printf("intel keyframes: front end ATE %.3f m, loop-closed %.3f m, %zu updates\n", front_end_m, loop_closed_m,
              updates.size());
  EXPECT_LT(loop_closed_m, 0.1);
  EXPECT_LT(loop_closed_m, 0.7 * front_end_m);
  EXPECT_EQ(agent.stats().keyframe_pose_updates, int(updates.size()));
}

TEST(AgentPipeline, WorksWithoutOdometry) {
  const Sequence s = make_sequence();
  AgentOptions o = test_options();
  o.use_odometry = false;
  AgentPipeline agent(RobotId(0), o);
  std::vector<Event> events;
  for (const Event& e : chronological(s))
    if (e.topic != 0) events.push_back(e);
  const AgentOutputs out = run(s, events, 1, &agent);
  EXPECT_GE(out.keyframes.size(), 8u);
  const SE2 end = s.truth.front() * agent.trajectory().back().pose;
  EXPECT_LT((end.translation() - s.truth.back().translation()).norm(), 0.05);
  EXPECT_EQ(agent.stats().scans_match_failed, 0);
}

TEST(AgentPipeline, BadInputIsCountedNotFatal) {
  AgentPipeline agent(RobotId(0), test_options());
  const auto room = testing::make_room();
  LaserScan scan = testing::ray_cast(room, SE2(), 0);
  scan.ranges_m[0] = std::numeric_limits<float>::quiet_NaN();
  scan.ranges_m[1] = -std::numeric_limits<float>::infinity();
  agent.add_odometry({0, SE2(), 0, 0});
  agent.add_scan(scan);
  LaserScan dead = testing::ray_cast(room, SE2(), kNsPerSec);
  std::fill(dead.ranges_m.begin(), dead.ranges_m.end(), std::numeric_limits<float>::quiet_NaN());
  agent.add_odometry({kNsPerSec, SE2(), 0, 0});
  agent.add_scan(dead);
  RgbdFrame bad = testing::render_rgbd(SE2(), {2, 0, 0.4}, 0.3, kNsPerSec / 2);
  bad.rgb.resize(10);
  agent.add_rgbd(bad);
  agent.add_scan(scan);  // out of order (stamp 0 < 1 s)
  const AgentOutputs out = agent.process(true);
  EXPECT_EQ(out.keyframes.size(), 1u);
  const AgentStats st = agent.stats();
  EXPECT_EQ(st.beams.nan_or_inf, 2 + 360);
  EXPECT_EQ(st.scans_too_few_points, 1);
  EXPECT_EQ(st.rgbd_invalid, 1);
  EXPECT_EQ(st.scans_out_of_order, 1);
  EXPECT_EQ(st.scans_matched, 1);
}

}  // namespace
}  // namespace cairn::agent
