// Landmarks at the base: alignment on shared markers, range-bearing nodes in the pose graph, and
// the end-to-end case of issue #4: two robots in a featureless field (no laser returns at all, so
// scans alone can never link them) whose multi-robot log, written in the text format and read back,
// links them through the markers both saw, with the markers recovered in the global frame.
#include "base_station/core/landmarks.h"

#include <gtest/gtest.h>

#include <random>
#include <sstream>

#include "base_station/core/landmark_test_util.h"
#include "base_station/core/multi_robot_mapper.h"
#include "common/multirobot_log.h"

namespace cairn::base {
namespace {

const std::map<LandmarkId, Eigen::Vector2d> kMarkers = {{LandmarkId(0), {2, 3}}, {LandmarkId(1), {5, 1}},
                                                        {LandmarkId(2), {8, 5}}, {LandmarkId(3), {3, 7}},
                                                        {LandmarkId(4), {7, 8}}, {LandmarkId(5), {10, 2}}};

/// Robot `robot` drives a circle of radius 3 m around `center` (world frame) at 0.5 m/s for one lap;
/// 10 Hz odometry (small seeded drift), featureless scans (all no-return) and range-bearing
/// observations of the markers within 5 m. `swap` relabels marker swap.first as swap.second.
void simulate_robot(RobotId robot, const Eigen::Vector2d& center, double phase_rad, uint32_t seed, MultiRobotLog* log,
                    std::pair<int, int> swap = {-1, -1}) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  RobotLogData& r = log->robot_data(robot);
  const double radius = 3.0, speed = 0.5, dt = 0.1;
  const int steps = int(2 * M_PI * radius / speed / dt);
  SE2 odom, prev_truth;
  for (int i = 0; i <= steps; ++i) {
    const double a = phase_rad + i * speed * dt / radius;
    const SE2 truth(center + radius * Eigen::Vector2d(std::cos(a), std::sin(a)), a + M_PI / 2);
    if (i > 0) {
      const SE2 d = prev_truth.between(truth);
      odom = odom * SE2(d.x() * (1 + 0.01 * n01(rng)), d.y() + 0.002 * n01(rng), d.yaw() + 0.002 * n01(rng));
    }
    prev_truth = truth;
    const StampNs t = sec_to_ns(10.0 + i * dt);
    r.odometry.push_back({t, odom, 0, 0});
    r.truth.push_back({t, truth});
    r.scans.push_back(testing::featureless_scan(t));
    for (const auto& [id, p] : kMarkers) {
      const Eigen::Vector2d q = truth.inverse() * p;
      if (q.norm() > 5.0 || q.norm() < 0.3) continue;  // out of view, or too close to see it whole
      const int label = id.value == swap.first ? swap.second : id.value;
      r.landmarks.push_back(LandmarkObservation{LandmarkId(label), t, q.norm() + 0.03 * n01(rng),
                                                std::atan2(q.y(), q.x()) + 0.01 * n01(rng), 0.03, 0.01});
    }
  }
}

/// Writes the log in the text format, reads it back, and merges both robots' keyframes.
MultiRobotLog round_trip(const MultiRobotLog& log) {
  std::stringstream ss;
  write_multirobot_log(ss, log, "synthetic featureless field with 6 markers");
  return parse_multirobot_log(ss, "synthetic.mrlog");
}

void merge(const MultiRobotLog& log, MultiRobotMapper* mapper) {
  const auto k0 = testing::keyframes_of(*log.robot(RobotId(0)), 5),
             k1 = testing::keyframes_of(*log.robot(RobotId(1)), 5);
  for (size_t i = 0; i < std::max(k0.size(), k1.size()); ++i) {
    if (i < k0.size()) mapper->add_keyframe(k0[i]);
    if (i < k1.size()) mapper->add_keyframe(k1[i]);
    if (i % 10 == 9) mapper->optimize();
  }
  mapper->optimize();
}

MultiRobotLog two_robot_log(std::pair<int, int> swap = {-1, -1}) {
  MultiRobotLog log;
  log.markers = kMarkers;
  simulate_robot(RobotId(0), {4, 4}, -M_PI / 2, 1, &log);
  simulate_robot(RobotId(1), {7, 5}, M_PI / 2, 2, &log, swap);
  return round_trip(log);
}

/// Largest error of the mapper's global landmark positions against the truth, expressed in the
/// global frame (= robot 0's start frame).
double max_landmark_error_m(const MultiRobotMapper& mapper, const MultiRobotLog& log, int* compared) {
  const SE2 T_global_world = log.robot(RobotId(0))->truth.front().pose.inverse();
  double worst = 0;
  *compared = 0;
  for (const auto& [id, p] : mapper.landmarks()) {
    worst = std::max(worst, (p - T_global_world * log.markers.at(id)).norm());
    ++*compared;
  }
  return worst;
}

TEST(Landmarks, FeaturelessRobotsLinkOnSharedMarkers) {
  const MultiRobotLog log = two_robot_log();
  MultiRobotMapper mapper;
  merge(log, &mapper);
  ASSERT_TRUE(mapper.linked(RobotId(1))) << (mapper.landmark_link_events().empty()
                                                 ? "no marker link event"
                                                 : mapper.landmark_link_events().back().reason);
  EXPECT_TRUE(mapper.landmark_link_events().back().accepted);
  int compared = 0;
  const double err = max_landmark_error_m(mapper, log, &compared);
  EXPECT_EQ(compared, int(kMarkers.size()));
  EXPECT_LT(err, 0.15) << "max marker position error";
  // Robot 1's start is recovered: its last keyframe's global pose against the truth.
  const Trajectory t1 = mapper.global_trajectory(RobotId(1));
  const SE2 truth =
      log.robot(RobotId(0))->truth.front().pose.inverse() * log.robot(RobotId(1))->truth[t1.size() * 5 - 5].pose;
  EXPECT_LT((t1.back().pose.translation() - truth.translation()).norm(), 0.2);
  std::printf("[landmarks] robot 1 linked: %s; max marker error %.3f m over %d markers; last pose error %.3f m\n",
              mapper.landmark_link_events().back().reason.c_str(), err, compared,
              (t1.back().pose.translation() - truth.translation()).norm());
}

TEST(Landmarks, WithoutMarkersFeaturelessRobotsStayUnlinked) {
  const MultiRobotLog log = two_robot_log();
  MapperOptions options;
  options.landmarks.enabled = false;
  MultiRobotMapper mapper(options);
  merge(log, &mapper);
  EXPECT_FALSE(mapper.linked(RobotId(1)));
  EXPECT_TRUE(mapper.landmarks().empty());
}

TEST(Landmarks, MisidentifiedMarkerIsDroppedNotMerged) {
  // Robot 1 reports marker 2 as marker 0: its "0" is 5.4 m away from robot 0's marker 0.
  const MultiRobotLog log = two_robot_log({2, 0});
  MultiRobotMapper mapper;
  merge(log, &mapper);
  ASSERT_FALSE(mapper.landmark_link_events().empty());
  if (mapper.linked(RobotId(1))) {  // linked on the consistent markers only: placed right
    const Trajectory t1 = mapper.global_trajectory(RobotId(1));
    const SE2 truth =
        log.robot(RobotId(0))->truth.front().pose.inverse() * log.robot(RobotId(1))->truth[t1.size() * 5 - 5].pose;
    EXPECT_LT((t1.back().pose.translation() - truth.translation()).norm(), 0.5);
  }
}

TEST(Landmarks, AlignmentNeedsEnoughConsistentSpreadMarkers) {
  LocalLandmarks a, b;
  const SE2 T_a_b(1.0, -2.0, 0.7);
  for (const auto& [id, p] : kMarkers) {
    a[id].sum_m = p;
    a[id].observations = 1;
    b[id].sum_m = T_a_b.inverse() * p;
    b[id].observations = 1;
  }
  LandmarkAlignment al = align_landmarks(a, b, 3, 0.3, 1.5);
  ASSERT_TRUE(al.ok) << al.reason;
  EXPECT_LT((al.T_a_b.translation() - T_a_b.translation()).norm(), 1e-9);
  EXPECT_NEAR(al.T_a_b.yaw(), T_a_b.yaw(), 1e-9);
  b[LandmarkId(3)].sum_m += Eigen::Vector2d(2.0, 0.0);  // one outlier: dropped
  al = align_landmarks(a, b, 3, 0.3, 1.5);
  ASSERT_TRUE(al.ok) << al.reason;
  ASSERT_EQ(al.dropped.size(), 1u);
  EXPECT_EQ(al.dropped[0], LandmarkId(3));
  EXPECT_NEAR(al.T_a_b.yaw(), T_a_b.yaw(), 1e-9);
  EXPECT_FALSE(align_landmarks(a, b, 7, 0.3, 1.5).ok);   // too few
  EXPECT_FALSE(align_landmarks(a, b, 3, 0.3, 50.0).ok);  // too little spread
}

TEST(Landmarks, PoseGraphRangeBearingRecoversPointAndPose) {
  // Two poses 4 m apart seeing two landmarks; pose 1's odometry is off by 0.5 m in y: the
  // landmark residuals (pose 0 pinned) pull it back.
  KeyframePoseGraph graph;
  const KeyframeId k0{RobotId(0), 0}, k1{RobotId(0), 1};
  ASSERT_TRUE(graph.add_node(k0, SE2()));
  ASSERT_TRUE(graph.add_node(k1, SE2(4, 0.5, 0)));
  graph.set_prior(PosePrior{k0, SE2(), Eigen::Matrix3d::Identity() * 1e6});
  graph.add_edge(PoseGraphEdge{k0, k1, SE2(4, 0.5, 0), Eigen::Vector3d(1, 1, 1).asDiagonal(), EdgeKind::kOdometry});
  const SE2 truth1(4, 0, 0);
  for (const Eigen::Vector2d& p : {Eigen::Vector2d(2, 3), Eigen::Vector2d(3, -2)}) {
    for (const auto& [id, T] : {std::pair{k0, SE2()}, std::pair{k1, truth1}}) {
      const Eigen::Vector2d q = T.inverse() * p;
      const LandmarkId lid(p.y() > 0 ? 1 : 2);
      ASSERT_TRUE(graph.add_landmark_edge(LandmarkEdge{id, lid, q.norm(), std::atan2(q.y(), q.x()), 0.01, 0.005}));
    }
  }
  EXPECT_FALSE(graph.add_landmark_edge(LandmarkEdge{k0, LandmarkId(1), std::nan(""), 0, 0.01, 0.01}));
  EXPECT_FALSE(graph.add_landmark_edge(LandmarkEdge{KeyframeId{RobotId(5), 0}, LandmarkId(1), 2, 0, 0.01, 0.01}));
  EXPECT_TRUE(graph.has_landmark_edges_from(k1));
  const PoseGraphSolveResult r = graph.solve();
  EXPECT_TRUE(r.converged) << r.reason;
  EXPECT_LT((graph.estimate(k1)->translation() - truth1.translation()).norm(), 0.02);
  EXPECT_LT((*graph.landmark_estimate(LandmarkId(1)) - Eigen::Vector2d(2, 3)).norm(), 0.02);
  EXPECT_EQ(graph.num_landmarks(), 2u);
  // A copy carries the landmarks and solves on its own.
  KeyframePoseGraph copy = graph;
  EXPECT_TRUE(copy.solve().converged);
  EXPECT_EQ(copy.landmark_estimates().size(), 2u);
}

}  // namespace
}  // namespace cairn::base
