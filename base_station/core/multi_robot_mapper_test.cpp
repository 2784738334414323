#include "base_station/core/multi_robot_mapper.h"

#include <gtest/gtest.h>

#include <random>

#include "base_station/core/synthetic_world_test_util.h"

namespace cairn::base {
namespace {

using testing::left_path;
using testing::make_keyframes;
using testing::make_object;
using testing::right_path;
using testing::room_walls;

const RobotId kR0(0), kR1(1), kR2(2);

double distance_to_walls(const Eigen::Vector2d& p) {
  double best = 1e9;
  for (const testing::Segment& s : room_walls()) {
    const Eigen::Vector2d e = s.b - s.a;
    const double t = std::clamp((p - s.a).dot(e) / e.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (s.a + t * e - p).norm());
  }
  return best;
}

bool occupied_near(const OccupancyGrid& grid, const Eigen::Vector2d& p) {
  const Eigen::Vector2i c = grid.cell_of(p);
  for (int dr = -1; dr <= 1; ++dr) {
    for (int dc = -1; dc <= 1; ++dc) {
      if (grid.known(c.x() + dc, c.y() + dr) && grid.probability(c.x() + dc, c.y() + dr) > 0.65) return true;
    }
  }
  return false;
}

/// These tests exercise placement by start hints: automatic loop detection is off so their exact
/// figures hold (multi_robot_mapper_merge_test.cpp covers automatic linking), and so are object constraints (the
/// victim both robots report 0.22 m apart would pull the keyframes; object_constraints_test.cpp).
MapperOptions hint_only_options() {
  MapperOptions o;
  o.detect_loops = false;
  o.object_constraints.enabled = false;
  return o;
}

/// Two linked robots in the synthetic room, with objects: a victim seen by both, a hazard seen by
/// robot 1 and a second victim (far from the first) seen by robot 0.
MultiRobotMapper make_two_robot_mapper() {
  MultiRobotMapper mapper(hint_only_options());
  mapper.set_robot_start(kR0, left_path()[0]);
  mapper.set_robot_start(kR1, right_path()[0]);
  for (const Keyframe& kf : make_keyframes(kR0, left_path(), room_walls()))
    EXPECT_TRUE(mapper.add_keyframe(kf).stored());
  for (const Keyframe& kf : make_keyframes(kR1, right_path(), room_walls()))
    EXPECT_TRUE(mapper.add_keyframe(kf).stored());
  mapper.add_object(make_object({kR0, 0}, "victim", {4.3, 3.5, 0.2}, 3, left_path()[3], 5));
  mapper.add_object(make_object({kR1, 0}, "victim", {4.1, 3.4, 0.2}, 4, right_path()[4], 15));
  mapper.add_object(make_object({kR1, 1}, "hazard", {8.0, 2.0, 0.1}, 1, right_path()[1]));
  mapper.add_object(make_object({kR0, 1}, "victim", {1.5, 5.5, 0.0}, 5, left_path()[5]));
  return mapper;
}

TEST(MultiRobotMapper, TwoRobotsBuildTheRoom) {
  MultiRobotMapper mapper = make_two_robot_mapper();
  const OptimizeResult r = mapper.optimize();
  EXPECT_TRUE(r.solve.converged) << r.solve.reason;
  EXPECT_EQ(r.nodes, 12);
  EXPECT_EQ(r.edges, 10);
  EXPECT_EQ(r.priors, 2);
  EXPECT_EQ(r.gap_edges, 0);
  for (size_t i = 0; i < left_path().size(); ++i) {
    const SE2 p = *mapper.global_pose({kR0, int32_t(i)});
    EXPECT_NEAR((p.translation() - left_path()[i].translation()).norm(), 0.0, 1e-6);
  }
  const OccupancyGrid& grid = mapper.global_map();
  // Wall samples away from corners: each has an occupied cell within one cell.
  const std::vector<testing::Segment> checked = {
      {{0, 1}, {0, 5}}, {{1, 6}, {9, 6}}, {{10, 1}, {10, 5}}, {{5, 0.3}, {5, 2.3}}, {{1, 0}, {4, 0}}};
  int hits = 0, samples = 0;
  for (const auto& s : checked) {
    for (double t = 0; t <= 1.0; t += 0.05, ++samples) hits += occupied_near(grid, s.a + t * (s.b - s.a));
  }
  EXPECT_GE(hits, samples * 95 / 100) << hits << "/" << samples;
  // No phantom walls: occupied cells lie on the walls.
  int occupied = 0, phantom = 0;
  for (int row = 0; row < grid.height(); ++row) {
    for (int col = 0; col < grid.width(); ++col) {
      if (!grid.known(col, row) || grid.probability(col, row) <= 0.65) continue;
      ++occupied;
      phantom += distance_to_walls(grid.cell_center_m(col, row)) > 0.1;
    }
  }
  EXPECT_GT(occupied, 200);
  EXPECT_LE(phantom, occupied / 100);
  // The middle of the room is free.
  const Eigen::Vector2i mid = grid.cell_of({3.0, 3.0});
  EXPECT_LT(grid.probability(mid.x(), mid.y()), 0.25);
  EXPECT_GT(mapper.mapped_area_m2(), 40.0);
  EXPECT_LT(mapper.mapped_area_m2(), 70.0);
}

TEST(MultiRobotMapper, MergesObjectsAcrossRobots) {
  MultiRobotMapper mapper = make_two_robot_mapper();
  mapper.optimize();
  const std::vector<GlobalObject> objects = mapper.objects();
  ASSERT_EQ(objects.size(), 3u);
  const GlobalObject& victim = objects[0];  // sorted by id: robot0/obj0 first
  EXPECT_EQ(victim.class_name, "victim");
  EXPECT_EQ(victim.reports.size(), 2u);
  ASSERT_EQ(victim.robots.size(), 2u);
  EXPECT_EQ(victim.robots[0], kR0);
  EXPECT_EQ(victim.robots[1], kR1);
  EXPECT_EQ(victim.observations, 20);
  // Observation-weighted: (5 * 4.3 + 15 * 4.1) / 20 = 4.15.
  EXPECT_NEAR(victim.position_m.x(), 4.15, 1e-6);
  EXPECT_NEAR(victim.position_m.y(), 3.425, 1e-6);
  EXPECT_NEAR(victim.position_m.z(), 0.2, 1e-6);
  EXPECT_FALSE(victim.cloud_global.empty());
  EXPECT_LE(victim.cloud_global.size(), 2 * 49u);
  EXPECT_FALSE(victim.thumbnail_jpeg.empty());
  EXPECT_EQ(objects[1].class_name, "victim");  // robot0/obj1, far from the first
  EXPECT_EQ(objects[2].class_name, "hazard");
  EXPECT_NEAR(objects[2].position_m.x(), 8.0, 1e-6);
  // A newer report of the same id replaces the old; an older one is refused.
  ObjectReport moved = make_object({kR1, 1}, "hazard", {8.2, 2.0, 0.1}, 1, right_path()[1]);
  moved.stamp_ns += 10;
  EXPECT_EQ(mapper.add_object(moved).status, AddStatus::kAccepted);
  EXPECT_NEAR(mapper.objects()[2].position_m.x(), 8.2, 1e-6);
  moved.stamp_ns -= 20;
  EXPECT_EQ(mapper.add_object(moved).status, AddStatus::kDuplicate);
  // Another class under a stored object's id never replaces it, however new.
  ObjectReport other = moved;
  other.class_name = "victim";
  other.stamp_ns += 1000;
  EXPECT_EQ(mapper.add_object(other).status, AddStatus::kConflict);
  EXPECT_EQ(mapper.objects()[2].class_name, "hazard");
}

TEST(MultiRobotMapper, UnlinkedRobotIsReportedNotPlaced) {
  MultiRobotMapper mapper = make_two_robot_mapper();
  mapper.optimize();
  const double area = mapper.mapped_area_m2();
  for (const Keyframe& kf : make_keyframes(kR2, right_path(), room_walls())) {
    EXPECT_EQ(mapper.add_keyframe(kf).status, AddStatus::kPending);
  }
  EXPECT_EQ(mapper.add_object(make_object({kR2, 0}, "exit", {9, 5, 0}, 0, right_path()[0])).status,
            AddStatus::kPending);
  const OptimizeResult r = mapper.optimize();
  EXPECT_EQ(r.unlinked_robots, 1);
  EXPECT_EQ(r.nodes, 12);
  const std::vector<RobotSummary> robots = mapper.robots();
  ASSERT_EQ(robots.size(), 3u);
  EXPECT_TRUE(robots[0].linked);
  EXPECT_FALSE(robots[2].linked);
  EXPECT_EQ(robots[2].keyframes, 6);
  EXPECT_EQ(robots[2].objects, 1);
  EXPECT_TRUE(mapper.global_trajectory(kR2).empty());
  EXPECT_FALSE(mapper.global_pose({kR2, 0}).has_value());
  EXPECT_DOUBLE_EQ(mapper.mapped_area_m2(), area);
  EXPECT_EQ(mapper.objects().size(), 3u);
  // Linking it later places it.
  mapper.set_robot_start(kR2, right_path()[0]);
  mapper.optimize();
  EXPECT_NEAR((mapper.global_pose({kR2, 5})->translation() - right_path()[5].translation()).norm(), 0.0, 1e-6);
  EXPECT_EQ(mapper.objects().size(), 4u);
}

TEST(MultiRobotMapper, BadInputIsRejectedAndNothingIsLost) {
  MultiRobotMapper mapper = make_two_robot_mapper();
  const size_t stored = mapper.keyframes().size();
  Keyframe nan_kf = make_keyframes(kR0, left_path(), room_walls())[2];
  nan_kf.id.seq = 40;
  nan_kf.T_local_base = SE2(NAN, 0, 0);
  AddResult r = mapper.add_keyframe(nan_kf);
  EXPECT_EQ(r.status, AddStatus::kRejected);
  EXPECT_NE(r.reason.find("non-finite"), std::string::npos) << r.reason;
  nan_kf.T_local_base = SE2();
  nan_kf.T_prev_this = SE2(0, 0, INFINITY);
  EXPECT_EQ(mapper.add_keyframe(nan_kf).status, AddStatus::kRejected);
  Keyframe bad_robot = nan_kf;
  bad_robot.id.robot = RobotId();
  EXPECT_EQ(mapper.add_keyframe(bad_robot).status, AddStatus::kRejected);
  Keyframe bad_seq = make_keyframes(kR0, left_path(), room_walls())[1];
  bad_seq.id.seq = -3;
  EXPECT_EQ(mapper.add_keyframe(bad_seq).status, AddStatus::kRejected);
  // The same keyframe again is a duplicate; another one under its seq (a robot restarted without
  // its state) is a conflict. Both refused, the stored keyframe unchanged.
  Keyframe dup = make_keyframes(kR0, left_path(), room_walls())[1];
  EXPECT_EQ(mapper.add_keyframe(dup).status, AddStatus::kDuplicate);
  dup.T_local_base = SE2(100, 100, 0);
  r = mapper.add_keyframe(dup);
  EXPECT_EQ(r.status, AddStatus::kConflict) << r.reason;
  EXPECT_NEAR(mapper.keyframes().at({kR0, 1}).T_local_base.x(), left_path()[0].between(left_path()[1]).x(), 1e-12);
  EXPECT_EQ(mapper.keyframes().size(), stored);
  // NaN object pose rejected; missing anchor kept pending until the anchor arrives.
  ObjectReport nan_obj = make_object({kR0, 7}, "victim", {2, 2, 0}, 1, left_path()[1]);
  nan_obj.T_anchor_object.translation().x() = NAN;
  EXPECT_EQ(mapper.add_object(nan_obj).status, AddStatus::kRejected);
  const SE2 future_pose(2.0, 5.0, 0.0);
  ObjectReport early = make_object({kR0, 8}, "hazard", {2.5, 5.0, 0}, 6, future_pose);
  r = mapper.add_object(early);
  EXPECT_EQ(r.status, AddStatus::kPending) << r.reason;
  EXPECT_EQ(mapper.pending_objects().size(), 1u);
  mapper.optimize();
  EXPECT_EQ(mapper.objects().size(), 3u);
  Keyframe kf6 = make_keyframes(kR0, {left_path()[0], future_pose}, room_walls())[1];
  kf6.id.seq = 6;
  kf6.T_prev_this = left_path()[5].between(future_pose);
  EXPECT_EQ(mapper.add_keyframe(kf6).status, AddStatus::kAccepted);
  mapper.optimize();
  EXPECT_TRUE(mapper.pending_objects().empty());
  ASSERT_EQ(mapper.objects().size(), 4u);
  EXPECT_NEAR(mapper.objects()[2].position_m.x(), 2.5, 1e-6);
}

TEST(MultiRobotMapper, OutOfOrderKeyframesAreBridgedThenChained) {
  MultiRobotMapper mapper(hint_only_options());
  mapper.set_robot_start(kR0, left_path()[0]);
  const std::vector<Keyframe> kfs = make_keyframes(kR0, left_path(), room_walls());
  for (int i : {0, 1, 3, 4, 5}) ASSERT_TRUE(mapper.add_keyframe(kfs[i]).stored());
  OptimizeResult r = mapper.optimize();
  EXPECT_EQ(r.gap_edges, 1);
  EXPECT_EQ(mapper.robots()[0].missing_keyframes, 1);
  EXPECT_NEAR((mapper.global_pose({kR0, 4})->translation() - left_path()[4].translation()).norm(), 0.0, 1e-6);
  ASSERT_EQ(mapper.add_keyframe(kfs[2]).status, AddStatus::kAccepted);
  r = mapper.optimize();
  EXPECT_EQ(r.gap_edges, 0);
  EXPECT_EQ(r.edges, 5);
  const Trajectory t = mapper.global_trajectory(kR0);
  ASSERT_EQ(t.size(), 6u);
  for (size_t i = 0; i < t.size(); ++i) {
    EXPECT_NEAR((t[i].pose.translation() - left_path()[i].translation()).norm(), 0.0, 1e-6);
  }
}

/// Two laps of an ellipse around the room's interior wall end: the second lap revisits the first.
std::vector<SE2> two_laps(int per_lap) {
  std::vector<SE2> p;
  for (int i = 0; i < 2 * per_lap; ++i) {
    const double a = 2.0 * M_PI * i / per_lap;
    p.push_back(
        SE2(5.0 + 3.2 * std::cos(a), 4.0 + 1.2 * std::sin(a), std::atan2(1.2 * std::cos(a), -3.2 * std::sin(a))));
  }
  return p;
}

/// The robot's keyframes along `path` with odometry perturbed (and the local poses composed from it).
std::vector<Keyframe> noisy_keyframes(RobotId robot, const std::vector<SE2>& path, unsigned seed) {
  std::vector<Keyframe> kfs = make_keyframes(robot, path, room_walls());
  std::mt19937 rng(seed);
  std::normal_distribution<double> n_xy(0.0, 0.01), n_yaw(0.0, 0.004);
  for (size_t i = 1; i < kfs.size(); ++i) {
    kfs[i].T_prev_this = kfs[i].T_prev_this * SE2(n_xy(rng), n_xy(rng), n_yaw(rng));
    kfs[i].T_local_base = kfs[i - 1].T_local_base * kfs[i].T_prev_this;
  }
  return kfs;
}

/// Largest distance between the mapper's poses and those of a batch solve of its graph restarted
/// from odometry (the optimum the incremental scheme must reach).
double gap_to_batch_optimum_m(const MultiRobotMapper& mapper) {
  KeyframePoseGraph batch = mapper.graph();
  std::map<KeyframeId, SE2> odometry;
  for (const auto& [id, kf] : mapper.keyframes()) {
    auto prev = odometry.find(KeyframeId{id.robot, id.seq - 1});
    odometry[id] = prev != odometry.end() ? prev->second * kf.T_prev_this : *mapper.global_pose(id);
  }
  batch.set_estimates(odometry);
  EXPECT_TRUE(batch.solve().converged);
  double worst = 0;
  for (const auto& [id, T] : batch.estimates())
    worst = std::max(worst, (T.translation() - mapper.global_pose(id)->translation()).norm());
  return worst;
}

TEST(MultiRobotMapper, IncrementalUpdatesSolveOnlyTheirWindow) {
  MapperOptions options = hint_only_options();
  options.incremental_graph = true;
  MultiRobotMapper mapper(options);
  mapper.set_robot_start(kR0, two_laps(16)[0]);
  mapper.set_robot_start(kR1, right_path()[0]);
  const std::vector<Keyframe> a = noisy_keyframes(kR0, two_laps(16), 1), b = noisy_keyframes(kR1, right_path(), 2);
  for (size_t i = 0; i < a.size(); ++i) {
    ASSERT_TRUE(mapper.add_keyframe(a[i]).stored());
    if (i < b.size()) ASSERT_TRUE(mapper.add_keyframe(b[i]).stored());
    const OptimizeResult r = mapper.optimize();
    EXPECT_TRUE(r.solve.converged) << r.solve.reason;
    EXPECT_FALSE(r.full_solve);
    // New keyframes and incremental_window_keyframes predecessors each, minus the gauge-free first.
    EXPECT_LE(r.solve.variable_blocks, 2 * (options.incremental_window_keyframes + 1)) << i;
    if (i % 3 == 0) mapper.global_map();  // incremental renders along the way
  }
  EXPECT_LT(gap_to_batch_optimum_m(mapper), 1e-6);
  // The incrementally kept map shows the map of the final poses: keyframes are drawn in arrival
  // order (robots interleaved) and small moves are not redrawn, so clamped log-odds may differ,
  // but the occupied / free / unknown classes agree.
  GlobalMapRenderer fresh(options.grid, options.map_render);
  for (const auto& [id, kf] : mapper.keyframes()) fresh.set_pose(kf, *mapper.global_pose(id));
  const OccupancyGrid& kept = mapper.global_map();
  const OccupancyGrid& full = fresh.render();
  int differ = 0, known = 0;
  for (int r = 0; r < full.height(); ++r) {
    for (int c = 0; c < full.width(); ++c) {
      const Eigen::Vector2i o = kept.cell_of(full.cell_center_m(c, r));
      known += full.known(c, r);
      auto cls = [](const OccupancyGrid& g, int col, int row) {
        return !g.known(col, row) ? 0 : g.probability(col, row) >= 0.65 ? 1 : g.probability(col, row) <= 0.25 ? 2 : 3;
      };
      differ += cls(full, c, r) != cls(kept, o.x(), o.y());
    }
  }
  EXPECT_GT(known, 1000);
  EXPECT_LT(differ, known / 100) << differ << " of " << known << " cells classified differently";
}

TEST(MultiRobotMapper, AfterLoopClosuresUpdatesReachTheFullSolveOptimum) {
  MapperOptions options;  // loop detection on
  options.incremental_graph = true;
  MultiRobotMapper mapper(options);
  const std::vector<SE2> path = two_laps(24);
  mapper.set_robot_start(kR0, path[0]);
  int full_solves = 0;
  for (const Keyframe& k : noisy_keyframes(kR0, path, 3)) {
    ASSERT_TRUE(mapper.add_keyframe(k).stored());
    full_solves += mapper.optimize().full_solve;
  }
  OptimizeResult r = mapper.optimize();
  for (int i = 0; i < 10 && r.full_solve && !r.solve.converged; ++i) r = mapper.optimize();  // idle: refine
  ASSERT_GT(r.loop_closures, 0) << "no loop closed: the test proves nothing";
  EXPECT_GT(full_solves, 0);
  EXPECT_LT(gap_to_batch_optimum_m(mapper), 1e-3);
  // Once converged an idle update solves nothing.
  r = mapper.optimize();
  EXPECT_FALSE(r.full_solve);
  EXPECT_EQ(r.solve.variable_blocks, 0);
}

}  // namespace
}  // namespace cairn::base

namespace cairn::base {
namespace {

TEST(ChainEdge, AnEdgeSurerThanTheFloorIsTakenAtTheFloor) {
  // An agent's odometry-only edge of a robot turning in place: next to no variance along. Taken as
  // given it was information 4e17, and the graph could no longer converge after a link.
  Keyframe prev, kf;
  prev.id = KeyframeId{RobotId(1), 4};
  kf.id = KeyframeId{RobotId(1), 5};
  kf.T_prev_this = SE2(0, 0, -0.45);
  kf.edge_covariance = Covariance3::Zero();
  kf.edge_covariance(0, 0) = kf.edge_covariance(1, 1) = 2.5e-18;
  kf.edge_covariance(2, 2) = 1e-3;
  const MapperOptions options;
  bool gap = true;
  const PoseGraphEdge e = chain_edge(MapperData(), prev, kf, options, &gap);
  EXPECT_FALSE(gap);
  const double max_xy = 1.0 / (options.chain_edge_min_sigma_xy_m * options.chain_edge_min_sigma_xy_m);
  EXPECT_NEAR(e.information(0, 0), max_xy, 1e-6 * max_xy);
  EXPECT_NEAR(e.information(1, 1), max_xy, 1e-6 * max_xy);
  EXPECT_NEAR(e.information(2, 2), 1e3, 1e-6);  // above the floor: as measured
  // An edge already looser than the floor is left as it is.
  kf.edge_covariance = Covariance3::Identity() * 0.01;
  EXPECT_NEAR(chain_edge(MapperData(), prev, kf, options, &gap).information(0, 0), 100.0, 1e-9);
}

}  // namespace
}  // namespace cairn::base
