#include "robot_agent/core/submap_loop_closer.h"

#include <gtest/gtest.h>

#include <ceres/cubic_interpolation.h>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>

#include "robot_agent/core/local_slam.h"
#include "robot_agent/core/test_util.h"

namespace cairn::agent {
namespace {

constexpr double kDeg = M_PI / 180.0;

ProbabilityGrid room_grid(const std::vector<testing::Segment>& room) {
  ProbabilityGrid grid(Eigen::Vector2d(-1, -1), 0.05, 40, 40);
  RangeDataInserter inserter;
  for (const SE2& p : {SE2(0, 0, 0), SE2(1.5, 0.5, 0.4), SE2(-1.5, -1.0, -0.7), SE2(1.0, -2.0, 2.0)}) {
    for (int k = 0; k < 5; ++k) inserter.insert(p, scan_to_points(testing::ray_cast(room, p, 0)), &grid);
  }
  return grid;
}

TEST(RangeDataInserter, HitsRaiseAndMissesLowerProbability) {
  ProbabilityGrid grid(Eigen::Vector2d(-5, -5), 0.05, 200, 200);
  RangeDataInserter inserter;
  const std::vector<Eigen::Vector2f> points = {{2.0f, 0.0f}};
  for (int i = 0; i < 10; ++i) inserter.insert(SE2(), points, &grid);
  const Eigen::Vector2i hit = grid.cell_of({2.01, 0.01}), free = grid.cell_of({1.0, 0.01});
  EXPECT_GT(grid.at(hit.x(), hit.y(), 0.f), 0.7f);
  EXPECT_LT(grid.at(free.x(), free.y(), 1.f), 0.45f);
  EXPECT_FALSE(grid.known(grid.cell_of({0.0, 1.0}).x(), grid.cell_of({0.0, 1.0}).y()));
  inserter.insert(SE2(0, 0, 0), {{20.0f, 0.0f}}, &grid);  // grows to fit
  EXPECT_TRUE(grid.contains(grid.cell_of({20.0, 0.0}).x(), grid.cell_of({20.0, 0.0}).y()));
  EXPECT_GT(grid.at(grid.cell_of({2.01, 0.01}).x(), grid.cell_of({2.01, 0.01}).y(), 0.f), 0.6f);
}

// field_line_max_gap_m: a wall sampled sparsely (a grazing 1-degree scan) becomes a continuous ridge
// of the likelihood field between its hits; a jump between two surfaces (no third hit on its line,
// or longer than the gap) does not.
TEST(RangeDataInserter, FieldLinesJoinSparseWallHitsOnly) {
  // Hits 0.4 m apart along the wall y = 1; then a jump to a far wall at x = 6.
  const std::vector<Eigen::Vector2f> points = {{1.0f, 1.0f}, {1.4f, 1.0f}, {1.8f, 1.0f},
                                               {2.2f, 1.0f}, {6.0f, 0.5f}, {6.0f, 0.1f}};
  RangeDataInserterOptions o, hits_only;
  o.field_line_max_gap_m = 0.6;
  hits_only.field_line_max_gap_m = 0.0;
  ProbabilityGrid lines(Eigen::Vector2d(-1, -1), 0.05, 160, 60), dots(Eigen::Vector2d(-1, -1), 0.05, 160, 60);
  RangeDataInserter(o).insert(SE2(), points, &lines);
  RangeDataInserter(hits_only).insert(SE2(), points, &dots);
  auto field = [](const ProbabilityGrid& g, double x, double y) {
    const Eigen::Vector2i c = g.cell_of({x, y});
    return g.field_at(c.x(), c.y());
  };
  EXPECT_GT(field(lines, 1.2, 1.0), 0.9f);  // between two wall hits
  EXPECT_GT(field(lines, 2.0, 1.0), 0.9f);
  EXPECT_LT(field(dots, 1.2, 1.0), 0.1f);                            // hits only: a gap in the wall
  EXPECT_NEAR(field(lines, 1.4, 1.0), field(dots, 1.4, 1.0), 1e-6);  // hits unchanged
  EXPECT_LT(field(lines, 4.0, 0.75), 0.1f);                          // 3.8 m jump: not joined
  EXPECT_LT(field(lines, 6.0, 0.3), 0.1f);                           // the far pair has no third hit on its line
  // Probabilities are untouched: only the field (what the matchers read) changes.
  const Eigen::Vector2i between = lines.cell_of({1.2, 1.0});
  EXPECT_EQ(lines.known(between.x(), between.y()), dots.known(between.x(), between.y()));
}

// Growth and cropping copy only the written-cell box: every cell must read the same at the same
// world position afterwards, and free space stops at max_free_space_length_m.
TEST(ProbabilityGrid, GrowthAndCropKeepEveryWrittenCell) {
  RangeDataInserterOptions o;
  o.max_free_space_length_m = 10.0;
  RangeDataInserter inserter(o);
  ProbabilityGrid grid(Eigen::Vector2d(-2, -2), 0.05, 80, 80);
  const std::vector<Eigen::Vector2f> points = {{1.5f, 0.0f}, {0.0f, 1.2f}, {-1.0f, -1.0f}};
  inserter.insert(SE2(), points, &grid);
  std::vector<std::pair<Eigen::Vector2d, float>> probes;
  for (double x = -1.9; x < 1.9; x += 0.1) {
    for (double y = -1.9; y < 1.9; y += 0.1) {
      const Eigen::Vector2i c = grid.cell_of({x, y});
      probes.push_back(
          {grid.cell_center_m(c.x(), c.y()), grid.known(c.x(), c.y()) ? grid.at(c.x(), c.y(), -1.f) : -1.f});
    }
  }
  inserter.insert(SE2(0, 0, 0), {{20.0f, 0.0f}}, &grid);  // grows along +x only
  const Eigen::Vector2i far_hit = grid.cell_of({20.01, 0.01}), free_end = grid.cell_of({12.0, 0.01});
  ASSERT_TRUE(grid.contains(far_hit.x(), far_hit.y()));
  EXPECT_GT(grid.at(far_hit.x(), far_hit.y(), 0.f), 0.5f);
  EXPECT_FALSE(grid.known(free_end.x(), free_end.y()));  // beyond 10 m of free space
  const Eigen::Vector2i free_near = grid.cell_of({5.0, 0.01});
  EXPECT_LT(grid.at(free_near.x(), free_near.y(), 1.f), 0.5f);
  grid.crop_to_known();
  int compared = 0;
  for (const auto& [p, before] : probes) {
    const Eigen::Vector2i c = grid.cell_of(p);
    if (before < 0.f) continue;
    ++compared;
    ASSERT_TRUE(grid.known(c.x(), c.y())) << p.transpose();
    // The second scan's free ray along +x may have lowered cells on the x axis.
    if (std::abs(p.y()) > 0.1) EXPECT_FLOAT_EQ(grid.at(c.x(), c.y(), -1.f), before) << p.transpose();
  }
  EXPECT_GT(compared, 10);
  const Eigen::Vector2i hit_after = grid.cell_of({20.01, 0.01});
  EXPECT_GT(grid.at(hit_after.x(), hit_after.y(), 0.f), 0.5f);
  EXPECT_GT(grid.field_at(hit_after.x(), hit_after.y()), 0.9f);  // the likelihood field moved with it
}

TEST(FastCorrelativeScanMatcher, FindsALargeOffsetAndCeresRefinesIt) {
  const auto room = testing::make_room();
  const ProbabilityGrid grid = room_grid(room);
  const FastCorrelativeScanMatcher fast(grid);
  const CeresScanMatcher ceres;
  for (const SE2& truth : {SE2(0.3, 0.2, 0.1), SE2(-1.0, -0.5, -1.2)}) {
    const auto points = voxel_filter_2d(scan_to_points(testing::ray_cast(room, truth, 0)), 0.08);
    const auto found = fast.match(truth * SE2(1.2, -0.9, 15 * kDeg), points, 2.5, 25 * kDeg, 0.5);
    ASSERT_TRUE(found);
    EXPECT_LT((found->pose.translation() - truth.translation()).norm(), 0.08);
    const CeresMatch refined = ceres.match(found->pose, points, grid);
    ASSERT_TRUE(refined.converged);
    EXPECT_LT((refined.pose.translation() - truth.translation()).norm(), 0.01);
    EXPECT_LT(std::abs(normalize_angle(refined.pose.yaw() - truth.yaw())), 0.5 * kDeg);
    // A score threshold above the best candidate's: no match.
    const auto best = fast.match(truth, points, 0.5, 5 * kDeg, 0.0);
    ASSERT_TRUE(best);
    EXPECT_FALSE(fast.match(truth, points, 0.5, 5 * kDeg, best->score + 0.005));
  }
}

// The score-surface covariance of a scan matched into a grid built from itself.
Eigen::Matrix2d surface_covariance(const std::vector<testing::Segment>& world, const SE2& pose) {
  ProbabilityGrid grid(Eigen::Vector2d(-2, -2), 0.05, 80, 80);
  RangeDataInserter inserter;
  const auto points = scan_to_points(testing::ray_cast(world, pose, 0));
  for (int k = 0; k < 5; ++k) inserter.insert(pose, points, &grid);
  const CeresMatch m = CeresScanMatcher().match(pose * SE2(0.02, -0.02, 0.01), points, grid);
  EXPECT_TRUE(m.converged);
  return score_surface_covariance(grid, m.pose, points);
}

std::vector<testing::Segment> corridor(double yaw, double half_width_m) {
  const Eigen::Vector2d axis(std::cos(yaw), std::sin(yaw)), normal(-std::sin(yaw), std::cos(yaw));
  std::vector<testing::Segment> walls;
  for (double side : {-half_width_m, half_width_m})
    walls.push_back({-40.0 * axis + side * normal, 40.0 * axis + side * normal});
  return walls;
}

TEST(ScoreSurfaceCovariance, LargeAlongACorridorSmallAndIsotropicInARoom) {
  for (const double yaw : {0.0, 0.5, 1.2}) {
    const Eigen::Vector2d axis(std::cos(yaw), std::sin(yaw)), normal(-std::sin(yaw), std::cos(yaw));
    const Eigen::Matrix2d c = surface_covariance(corridor(yaw, 1.0), SE2(0, 0, 0.2));
    EXPECT_GT(axis.dot(c * axis), 10.0 * normal.dot(c * normal)) << "yaw " << yaw << "\n" << c;
    EXPECT_GT(axis.dot(c * axis), 0.004) << c;  // sigma > 6 cm (the window is +-0.8 m)
    EXPECT_LT(normal.dot(c * normal), 0.002) << c;
  }
  const Eigen::Matrix2d r = surface_covariance(testing::make_room(), SE2(0.3, 0.2, 0.1));
  const Eigen::Vector2d ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(r).eigenvalues();
  EXPECT_GT(ev(0), 0.3 * ev(1)) << r;  // nearly isotropic
  EXPECT_LT(ev(1), 0.002) << r;        // and small
}

// A grid with a random likelihood field and probabilities, and scan points scattered over it and
// beyond its edges (so the searches' clipped windows are exercised), more than 257 of them (the
// 16-bit row accumulation works in chunks).
struct RandomGridAndScan {
  ProbabilityGrid grid{Eigen::Vector2d(-2.0, -1.5), 0.05, 83, 61};
  std::vector<Eigen::Vector2f> points;
  explicit RandomGridAndScan(unsigned seed, int num_points = 700) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> col(0, grid.width() - 1), row(0, grid.height() - 1);
    std::uniform_real_distribution<double> p(0.1, 0.9);
    for (int i = 0; i < 400; ++i) {
      const int c = col(rng), r = row(rng);
      grid.splat_hit(c, r, 1.0);
      grid.set_probability(c, r, float(p(rng)));
    }
    std::uniform_real_distribution<float> x(-2.6f, 2.6f), y(-2.2f, 1.9f);
    for (int i = 0; i < num_points; ++i) points.emplace_back(x(rng), y(rng));
  }
};

// score_surface_covariance's one-cell lattice goes through the correlative search's 16-bit SIMD row
// accumulation; it must give exactly the sums of the plain per-offset loop.
TEST(ScoreSurfaceCovariance, RowAccumulationEqualsPointwiseSums) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const RandomGridAndScan data(seed);
    const ProbabilityGrid& grid = data.grid;
    ScoreSurfaceOptions o;
    o.max_points = 0;  // every point
    o.window_m = 0.4;
    const SE2 T(0.1, -0.05, 0.3);
    // Reference: every offset summed point by point, weighted the same way.
    const int k = 8, side = 2 * k + 1, w = grid.width(), h = grid.height();
    std::vector<Eigen::Vector2i> cells;
    for (const auto& p : data.points) cells.push_back(grid.cell_of(T * p.cast<double>()));
    std::vector<double> score(size_t(side) * side);
    for (int iy = 0; iy < side; ++iy) {
      for (int ix = 0; ix < side; ++ix) {
        int sum = 0;
        for (const auto& c : cells) {
          const int col = c.x() + ix - k, row = c.y() + iy - k;
          if (col >= 0 && row >= 0 && col < w && row < h) sum += grid.field()[size_t(row) * w + col];
        }
        score[size_t(iy) * side + ix] = sum / (255.0 * double(cells.size()));
      }
    }
    const Eigen::Matrix2d expected = covariance_of_score_lattice(score, k, 0.05, o.temperature);
    const Eigen::Matrix2d got = score_surface_covariance(grid, T, data.points, o);
    for (int i = 0; i < 4; ++i)
      EXPECT_DOUBLE_EQ(got(i), expected(i)) << "seed " << seed << "\n" << got << "\n" << expected;
  }
}

// Reads the probability grid for ceres::BiCubicInterpolator the way the scan matcher's reference does.
struct ProbabilityCostGrid {
  enum { DATA_DIMENSION = 1 };
  const ProbabilityGrid& grid;
  void GetValue(int row, int col, double* f) const { *f = 1.0 - double(grid.at(col, row, grid.fill_probability())); }
};

// interpolated_score reads interior cells directly; it must equal Ceres' bicubic interpolator
// everywhere, inside and across the grid's edges.
TEST(CeresScanMatcher, InterpolatedScoreEqualsCeresBicubic) {
  const RandomGridAndScan data(4, 300);
  const ProbabilityCostGrid adapter{data.grid};
  const ceres::BiCubicInterpolator<ProbabilityCostGrid> interpolator(adapter);
  for (const SE2& T : {SE2(0, 0, 0), SE2(0.37, -0.21, 0.4), SE2(-1.3, 0.8, -2.0)}) {
    double sum = 0.0;
    for (const auto& p : data.points) {
      const double c = std::cos(T.yaw()), s = std::sin(T.yaw()), px = p.x(), py = p.y();
      const double col = (c * px - s * py + T.x() - data.grid.origin_m().x()) * (1.0 / 0.05) - 0.5;
      const double row = (s * px + c * py + T.y() - data.grid.origin_m().y()) * (1.0 / 0.05) - 0.5;
      double f;
      interpolator.Evaluate(row, col, &f);
      sum += 1.0 - f;
    }
    EXPECT_DOUBLE_EQ(interpolated_score(T, data.points, data.grid), sum / double(data.points.size()));
  }
}

// The covariance is an output only: turning it off must not change the match.
TEST(CeresScanMatcher, CovarianceIsOptionalAndDoesNotChangeTheMatch) {
  const ProbabilityGrid grid = room_grid(testing::make_room());
  const std::vector<Eigen::Vector2f> points =
      scan_to_points(testing::ray_cast(testing::make_room(), SE2(0.2, 0.1, 0.1), 0));
  CeresScanMatcherOptions with, without;
  without.compute_covariance = false;
  const CeresMatch a = CeresScanMatcher(with).match(SE2(0.25, 0.05, 0.13), points, grid);
  const CeresMatch b = CeresScanMatcher(without).match(SE2(0.25, 0.05, 0.13), points, grid);
  ASSERT_TRUE(a.converged);
  EXPECT_EQ(a.pose.vector(), b.pose.vector());
  EXPECT_EQ(a.score, b.score);
  EXPECT_NEAR(a.pose.x(), 0.2, 0.03);
  EXPECT_NEAR(a.pose.y(), 0.1, 0.03);
  const Eigen::SelfAdjointEigenSolver<Covariance3> es(a.covariance);
  EXPECT_GT(es.eigenvalues().minCoeff(), 0.0) << a.covariance;  // positive definite, floor included
  EXPECT_EQ(b.covariance, Covariance3::Identity());
}

// Rays crossing the same free cell lower it once per scan, however many of them cross it; no
// update marker is left behind.
TEST(RangeDataInserter, FreeCellsAreUpdatedOncePerScan) {
  ProbabilityGrid grid(Eigen::Vector2d(-5, -5), 0.05, 200, 200);
  RangeDataInserterOptions o;
  const RangeDataInserter inserter(o);
  std::vector<Eigen::Vector2f> points;
  for (int i = 0; i < 360; ++i) points.emplace_back(3.0f * std::cos(i * kDeg), 3.0f * std::sin(i * kDeg));
  inserter.insert(SE2(0.01, 0.02, 0.0), points, &grid);
  const uint16_t once = compute_update_table(o.miss_probability)[kUnknownValue] - kUpdateMarker;
  for (const Eigen::Vector2d q : {Eigen::Vector2d(0.06, 0.0), Eigen::Vector2d(0.0, -0.1), Eigen::Vector2d(1.0, 1.0)}) {
    const Eigen::Vector2i c = grid.cell_of(q);
    EXPECT_EQ(grid.values()[size_t(c.y()) * grid.width() + c.x()], once) << q.transpose();
  }
  for (uint16_t v : grid.values()) ASSERT_LT(v, kUpdateMarker);
  inserter.insert(SE2(0.01, 0.02, 0.0), points, &grid);
  const Eigen::Vector2i c = grid.cell_of({1.0, 1.0});
  EXPECT_EQ(grid.values()[size_t(c.y()) * grid.width() + c.x()],
            compute_update_table(o.miss_probability)[once] - kUpdateMarker);
}

// Local SLAM made to trust drifting odometry (huge Ceres regularisers, no correlative search), two
// laps of a square: without loop closure the end drifts; with it the second lap snaps onto the first.
double two_laps_end_error_m(bool loop_closure) {
  const auto room = testing::make_room();
  std::vector<SE2> truth;
  SE2 pose(-2.0, -2.0, 0.0);
  truth.push_back(pose);
  for (int lap = 0; lap < 2; ++lap) {
    for (int side = 0; side < 4; ++side) {
      for (int i = 0; i < 20; ++i) truth.push_back(pose = pose * SE2(0.2, 0.0, 0.0));
      for (int i = 0; i < 3; ++i) truth.push_back(pose = pose * SE2(0.0, 0.0, 30 * kDeg));
    }
  }
  LocalSlamOptions o;
  o.matcher.use_correlative = false;
  o.matcher.ceres.translation_weight = o.matcher.ceres.rotation_weight = 1e4;
  o.submaps.scans_per_submap = 10;
  o.loop_closure.enabled = loop_closure;
  o.loop_closure.search_every_n_nodes = 4;
  o.loop_closure.optimize_every_n_nodes = 10;
  LocalSlam slam(o);
  SE2 odom = truth.front();
  for (size_t i = 0; i < truth.size(); ++i) {
    if (i > 0) {
      const SE2 d = truth[i - 1].between(truth[i]);
      odom = odom * SE2(1.02 * d.x(), d.y(), d.yaw() + 2.0 * kDeg * d.translation().norm());
    }
    slam.add_scan(testing::ray_cast(room, truth[i], StampNs(i) * kNsPerSec / 5, 360, 0.005, unsigned(i)),
                  truth.front().inverse() * odom);
  }
  slam.finish();
  const SE2 end = truth.front() * slam.optimized_trajectory().back().pose;
  return (end.translation() - truth.back().translation()).norm();
}

TEST(SubmapLoopCloser, ClosesASyntheticLoop) {
  const double open = two_laps_end_error_m(false);
  const double closed = two_laps_end_error_m(true);
  EXPECT_GT(open, 0.3);
  EXPECT_LT(closed, 0.15);
  EXPECT_LT(closed, 0.3 * open);
  std::cout << "end error: open loop " << open << " m, closed " << closed << " m\n";
}

}  // namespace
}  // namespace cairn::agent
