// Objects of interest as pose-graph constraints (issue #4): two linked robots whose relative
// placement is off (a start hint 0.3 m / 2 deg wrong, featureless scans: no scan closure can fix it)
// both report the same four objects; the object observations pull them into agreement. A wrongly
// merged object must not bend the map, a merge that goes away takes its edges with it, and bad
// reports change nothing.
#include "base_station/core/object_constraints.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>

#include "base_station/core/multi_robot_mapper.h"
#include "base_station/core/synthetic_world_test_util.h"

namespace cairn::base {
namespace {

using testing::make_object;

struct Scene {
  std::vector<SE2> path0, path1;  ///< world poses of the keyframes
  std::vector<Eigen::Vector3d> objects;
  std::vector<std::string> classes;
};

/// Robot 0 drives east along y = 0, robot 1 west along y = 3; four objects between them.
Scene scene() {
  Scene s;
  for (int i = 0; i <= 12; ++i) s.path0.emplace_back(0.5 * i, 0.0, 0.0);
  for (int i = 0; i <= 12; ++i) s.path1.emplace_back(6.0 - 0.5 * i, 3.0, M_PI);
  s.objects = {{1.0, 1.5, 0.3}, {2.5, 1.5, 0.3}, {4.0, 1.5, 0.3}, {5.5, 1.5, 0.3}};
  s.classes = {"victim", "hazard", "exit", "victim"};
  return s;
}

/// Featureless keyframes (no laser return at all) with exact odometry, local frame = first pose.
std::vector<Keyframe> keyframes(RobotId robot, const std::vector<SE2>& path) {
  std::vector<Keyframe> out;
  for (size_t i = 0; i < path.size(); ++i) {
    Keyframe kf;
    kf.id = KeyframeId{robot, int32_t(i)};
    kf.stamp_ns = StampNs(i + 1) * kNsPerSec;
    kf.T_local_base = path.front().between(path[i]);
    if (i > 0) kf.T_prev_this = path[i - 1].between(path[i]);
    kf.scan.angle_min_rad = float(-M_PI);
    kf.scan.angle_increment_rad = float(M_PI / 90);
    kf.scan.range_max_m = 8.f;
    kf.scan.ranges_m.assign(180, std::numeric_limits<float>::infinity());
    out.push_back(kf);
  }
  return out;
}

/// Each robot reports every object once, from its keyframe nearest to the object.
std::vector<ObjectReport> reports(RobotId robot, const std::vector<SE2>& path, const Scene& s) {
  std::vector<ObjectReport> out;
  for (size_t k = 0; k < s.objects.size(); ++k) {
    size_t best = 0;
    for (size_t i = 1; i < path.size(); ++i) {
      if ((path[i].translation() - s.objects[k].head<2>()).norm() <
          (path[best].translation() - s.objects[k].head<2>()).norm()) {
        best = i;
      }
    }
    out.push_back(make_object(ObjectId{robot, int32_t(k)}, s.classes[k], s.objects[k], int32_t(best), path[best]));
  }
  return out;
}

MapperOptions options(bool objects_on) {
  MapperOptions o;
  o.detect_loops = false;  // the scans are featureless anyway: no scan closure is possible
  // Loose start hints stand in for a link whose placement is off (e.g. by a few scan closures):
  // a tight prior would pin the error whatever the objects say.
  o.start_prior_sigma_xy_m = 1.0;
  o.start_prior_sigma_yaw_rad = 0.2;
  o.object_constraints.enabled = objects_on;
  return o;
}

/// Builds the mapper: robot 0 hinted at its true start, robot 1 at `hint1`; then optimises until
/// the refinement is done. `edit` may change robot 1's reports before they are added.
template <typename Edit>
OptimizeResult run(MultiRobotMapper* mapper, const Scene& s, const SE2& hint1, Edit edit) {
  mapper->set_robot_start(RobotId(0), s.path0.front());
  mapper->set_robot_start(RobotId(1), hint1);
  for (const Keyframe& kf : keyframes(RobotId(0), s.path0)) EXPECT_TRUE(mapper->add_keyframe(kf).stored());
  for (const Keyframe& kf : keyframes(RobotId(1), s.path1)) EXPECT_TRUE(mapper->add_keyframe(kf).stored());
  OptimizeResult r = mapper->optimize();
  std::vector<ObjectReport> r1 = reports(RobotId(1), s.path1, s);
  edit(&r1);
  for (const ObjectReport& o : reports(RobotId(0), s.path0, s))
    EXPECT_EQ(mapper->add_object(o).status, AddStatus::kAccepted);
  for (const ObjectReport& o : r1) EXPECT_EQ(mapper->add_object(o).status, AddStatus::kAccepted);
  for (int i = 0; i < 3 || (mapper->refinement_pending() && i < 30); ++i) r = mapper->optimize();
  return r;
}
OptimizeResult run(MultiRobotMapper* mapper, const Scene& s, const SE2& hint1) {
  return run(mapper, s, hint1, [](std::vector<ObjectReport>*) {});
}

/// Largest position error of robot 1's keyframes in robot 0's first keyframe frame (the robots'
/// relative error; the common gauge does not count).
double relative_error_m(const MultiRobotMapper& mapper, const Scene& s) {
  const SE2 est0 = *mapper.global_pose(KeyframeId{RobotId(0), 0});
  double worst = 0.0;
  for (size_t i = 0; i < s.path1.size(); ++i) {
    const SE2 est = est0.inverse() * *mapper.global_pose(KeyframeId{RobotId(1), int32_t(i)});
    const SE2 truth = s.path0.front().inverse() * s.path1[i];
    worst = std::max(worst, (est.translation() - truth.translation()).norm());
  }
  return worst;
}

/// Robot 1's true start, 0.3 m and 2 degrees off.
SE2 wrong_hint(const Scene& s) { return SE2(0.0, 0.3, 0.035) * s.path1.front(); }

TEST(ObjectConstraints, SharedObjectsPullLinkedRobotsIntoAgreement) {
  const Scene s = scene();
  MultiRobotMapper off(options(false)), on(options(true));
  const OptimizeResult r_off = run(&off, s, wrong_hint(s));
  const OptimizeResult r_on = run(&on, s, wrong_hint(s));
  // The merge joined each object's two reports (the error is within its cross-robot gate).
  ASSERT_EQ(on.objects().size(), s.objects.size());
  for (const GlobalObject& o : on.objects()) EXPECT_EQ(o.robots.size(), 2u) << to_string(o.id);
  EXPECT_EQ(r_off.object_edges, 0);
  EXPECT_EQ(r_on.object_edges, 8);
  EXPECT_EQ(r_on.constrained_objects, 4);
  EXPECT_EQ(on.graph().object_estimates().size(), 4u);
  EXPECT_TRUE(on.graph().landmark_estimates().empty()) << "objects must not appear as markers";
  const double e_off = relative_error_m(off, s), e_on = relative_error_m(on, s);
  std::printf("[objects] robots' relative error: %.3f m without object constraints, %.3f m with\n", e_off, e_on);
  EXPECT_GT(e_off, 0.25) << "without the objects nothing corrects the hint";
  EXPECT_LT(e_on, 0.05);
  EXPECT_LT(e_on, 0.2 * e_off);
  // The object nodes sit where the objects are, relative to robot 0 (both starts are loose priors:
  // the common gauge splits the hint's error, the relative geometry is what the objects fix).
  const SE2 est0 = *on.global_pose(KeyframeId{RobotId(0), 0});
  for (const auto& [id, p] : on.graph().object_estimates()) {
    const Eigen::Vector2d truth = s.path0.front().inverse() * Eigen::Vector2d(s.objects[size_t(id.seq)].head<2>());
    EXPECT_LT((est0.inverse() * p - truth).norm(), 0.05) << to_string(id);
  }
}

TEST(ObjectConstraints, SameResultWithTheGraphRebuiltEveryUpdate) {
  const Scene s = scene();
  MapperOptions o = options(true);
  o.incremental_graph = false;
  MultiRobotMapper rebuilt(o), live(options(true));
  EXPECT_EQ(run(&rebuilt, s, wrong_hint(s)).object_edges, 8);
  run(&live, s, wrong_hint(s));
  EXPECT_NEAR(relative_error_m(rebuilt, s), relative_error_m(live, s), 0.01);
  EXPECT_LT(relative_error_m(rebuilt, s), 0.05);
}

TEST(ObjectConstraints, WrongMergeDoesNotBendTheMap) {
  const Scene s = scene();
  // Robot 1's report of object 2 is 0.4 m off, still within the cross-robot merge gate: a wrong
  // merge. Both robots start hinted exactly (loosely): the truth is the right answer.
  auto shift = [](std::vector<ObjectReport>* r) { (*r)[2].T_anchor_object.translation().x() += 0.4; };
  MultiRobotMapper robust(options(true));
  const OptimizeResult r = run(&robust, s, s.path1.front(), shift);
  MapperOptions plain_options = options(true);
  plain_options.graph.object_loss = {RobustLossType::kNone, 1.0};
  MultiRobotMapper plain(plain_options);
  run(&plain, s, s.path1.front(), shift);
  bool merged = false;
  for (const GlobalObject& o : robust.objects()) merged |= o.id == ObjectId{RobotId(0), 2} && o.robots.size() == 2;
  ASSERT_TRUE(merged) << "the test needs the wrong report merged";
  EXPECT_EQ(r.object_edges, 8) << "the wrong merge's observations are in the graph";
  const double e_robust = relative_error_m(robust, s), e_plain = relative_error_m(plain, s);
  std::printf("[objects] one report 0.4 m off: relative error %.3f m (Cauchy), %.3f m (least squares)\n", e_robust,
              e_plain);
  EXPECT_LT(e_robust, 0.06);
  EXPECT_LT(e_robust, e_plain);
}

TEST(ObjectConstraints, UndoneMergeTakesItsEdgesOut) {
  const Scene s = scene();
  MultiRobotMapper mapper(options(true));
  ASSERT_EQ(run(&mapper, s, s.path1.front()).object_edges, 8);
  // A newer version of robot 1's report of object 0, 2 m away: no longer the same object.
  ObjectReport moved = reports(RobotId(1), s.path1, s)[0];
  moved.stamp_ns += kNsPerSec;
  moved.T_anchor_object.translation().y() += 2.0;
  ASSERT_EQ(mapper.add_object(moved).status, AddStatus::kAccepted);
  const OptimizeResult r = mapper.optimize();
  EXPECT_EQ(r.object_edges, 6);
  EXPECT_EQ(r.constrained_objects, 3);
  EXPECT_EQ(mapper.graph().landmark_edges().size(), 6u) << "the live graph was rebuilt without them";
  EXPECT_LT(relative_error_m(mapper, s), 0.02);
}

TEST(ObjectConstraints, BadReportIsRejectedAndChangesNothing) {
  const Scene s = scene();
  MultiRobotMapper mapper(options(true));
  run(&mapper, s, wrong_hint(s));
  const std::vector<ObjectConstraint> before = mapper.object_observations();
  const Eigen::Vector3d stored = mapper.object_reports().at(ObjectId{RobotId(1), 1}).T_anchor_object.translation();
  ObjectReport bad = reports(RobotId(1), s.path1, s)[1];
  bad.stamp_ns += kNsPerSec;  // newer: would replace the stored one
  bad.T_anchor_object.translation().x() += 1.0;
  bad.covariance(0, 0) = std::numeric_limits<double>::quiet_NaN();
  const AddResult added = mapper.add_object(bad);
  EXPECT_EQ(added.status, AddStatus::kRejected);
  EXPECT_NE(added.reason.find("covariance"), std::string::npos) << added.reason;
  EXPECT_EQ(mapper.object_reports().at(ObjectId{RobotId(1), 1}).T_anchor_object.translation(), stored);
  mapper.optimize();
  EXPECT_TRUE(same_constraints(before, mapper.object_observations()));
}

TEST(ObjectConstraints, OnlyVerifiedMultiAnchorClustersQualify) {
  const Scene s = scene();
  std::map<ObjectId, ObjectReport> stored;
  const std::vector<ObjectReport> r0 = reports(RobotId(0), s.path0, s), r1 = reports(RobotId(1), s.path1, s);
  for (const ObjectReport& r : r0) stored[r.id] = r;
  for (const ObjectReport& r : r1) stored[r.id] = r;
  ObjectReport twice = r0[0];  // robot 0 again, from the same anchor
  twice.id.seq = 10;
  stored[twice.id] = twice;
  GlobalObject pair, same_anchor, single;
  pair.id = r0[1].id;
  pair.reports = {r0[1].id, r1[1].id};
  same_anchor.id = r0[0].id;
  same_anchor.reports = {r0[0].id, twice.id};
  single.id = r0[2].id;
  single.reports = {r0[2].id};
  const ObjectMergeOptions merge;
  ObjectConstraintOptions o;
  std::vector<ObjectConstraint> c = object_constraints({pair, same_anchor, single}, stored, o, merge);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c[0].report, r0[1].id);
  EXPECT_EQ(c[1].report, r1[1].id);
  for (const ObjectConstraint& x : c) {
    EXPECT_EQ(x.edge.landmark, PointNodeId(pair.id));
    EXPECT_GE(x.edge.sigma_range_m, o.min_sigma_m - 1e-12) << "covariance floored";
    EXPECT_NEAR(x.edge.sigma_bearing_rad * x.edge.range_m, o.min_sigma_m, 1e-9);
  }
  stored[r1[1].id].cloud.resize(3);  // merged by the centroid gate alone: not verified
  EXPECT_TRUE(object_constraints({pair}, stored, o, merge).empty());
  stored[r1[1].id] = r1[1];
  o.enabled = false;
  EXPECT_TRUE(object_constraints({pair}, stored, o, merge).empty());
}

TEST(ObjectConstraints, ObjectAndMarkerNodesNeverCollide) {
  KeyframePoseGraph graph;
  const KeyframeId k{RobotId(0), 0};
  ASSERT_TRUE(graph.add_node(k, SE2()));
  graph.set_prior(PosePrior{k, SE2()});
  ASSERT_TRUE(graph.add_landmark_edge(LandmarkEdge{k, LandmarkId(0), 2.0, 0.0, 0.05, 0.02}));
  ASSERT_TRUE(graph.add_landmark_edge(LandmarkEdge{k, ObjectId{RobotId(0), 0}, 3.0, M_PI / 2, 0.05, 0.02}));
  EXPECT_FALSE(graph.add_landmark_edge(LandmarkEdge{k, ObjectId{RobotId(-1), 0}, 3.0, 0.0, 0.05, 0.02}));
  EXPECT_TRUE(graph.solve().converged);
  EXPECT_EQ(graph.num_landmarks(), 2u);
  ASSERT_EQ(graph.landmark_estimates().size(), 1u);
  ASSERT_EQ(graph.object_estimates().size(), 1u);
  EXPECT_LT((graph.landmark_estimates().at(LandmarkId(0)) - Eigen::Vector2d(2, 0)).norm(), 1e-6);
  EXPECT_LT((graph.object_estimates().at(ObjectId{RobotId(0), 0}) - Eigen::Vector2d(0, 3)).norm(), 1e-6);
}

}  // namespace
}  // namespace cairn::base
