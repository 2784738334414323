// Grid planning on hand-drawn grids (0.1 m cells): classification and its box, frontier pieces,
// Dijkstra lengths (walls, near-wall and unknown costs), path extraction, inflation (a door the
// robot fits through and one it does not), the coarse copy and the nearest reachable frontier.
#include "common/grid_planning.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/grid_drawing_test_util.h"

namespace cairn {
namespace {

constexpr double kRes = 0.1;

/// A 10 m x 6 m grid at 0.1 m, all unknown (common/grid_drawing_test_util.h).
using Drawing = testing::GridDrawing;

double length_at(const PlanningGrid& g, const DistanceField& f, const Eigen::Vector2d& p_m) {
  return f.length_m[g.index(g.cell_of(p_m))];
}

TEST(GridPlanning, ClassifiesWithinTheKnownBoxPlusOneCell) {
  Drawing d;
  d.free(2, 2, 3, 3);
  d.wall(3, 2, 3.1, 3);
  d.paint(2, 2, 2.1, 2.1, 0.1f);  // known but undecided: unknown
  const PlanningGrid g(d.grid);
  ASSERT_FALSE(g.empty());
  EXPECT_EQ(g.width(), 11 + 2);  // x 2..3.1: 11 cells, one unknown cell each side
  EXPECT_EQ(g.height(), 10 + 2);
  EXPECT_EQ(g.state(g.index(g.cell_of({2.55, 2.55}))), CellState::kFree);
  EXPECT_EQ(g.state(g.index(g.cell_of({3.05, 2.55}))), CellState::kOccupied);
  EXPECT_EQ(g.state(g.index(g.cell_of({2.05, 2.05}))), CellState::kUnknown);
  EXPECT_EQ(g.state(g.index(0, 0)), CellState::kUnknown);
  EXPECT_NEAR(g.centre_m({1, 1}).x(), 2.05, 1e-9);
  EXPECT_NEAR(g.centre_m({1, 1}).y(), 2.05, 1e-9);
  EXPECT_EQ(g.cell_of({2.05, 2.05}), Eigen::Vector2i(1, 1));

  // Points to include grow the box; nothing known and nothing included: empty.
  const PlanningGrid wider(d.grid, {}, {{6.05, 2.5}});
  EXPECT_EQ(wider.width(), 41 + 2);
  EXPECT_TRUE(PlanningGrid(Drawing().grid).empty());
}

TEST(GridPlanning, FrontiersAreFreeCellsNextToUnknownInConnectedPieces) {
  Drawing d;
  d.room();
  d.paint(9, 2, 9.1, 3, 0.f);    // a 1 m opening in the east wall: unknown beyond
  d.paint(4, 3, 4.1, 3.1, 0.f);  // one unknown cell in the room: its 4 neighbours are frontier
  const PlanningGrid g(d.grid);
  std::vector<FrontierPiece> pieces = frontier_pieces(g);
  ASSERT_EQ(pieces.size(), 2u);
  std::sort(pieces.begin(), pieces.end(), [](const auto& a, const auto& b) { return a.size() > b.size(); });
  EXPECT_EQ(pieces[0].size(), 10u);  // the free column at x = 8.95 beside the opening
  for (const auto& cell : pieces[0]) EXPECT_NEAR(g.centre_m(cell).x(), 8.95, 1e-9);
  EXPECT_EQ(pieces[1].size(), 4u);
  // Closed again: nothing left.
  d.wall(9, 2, 9.1, 3);
  d.free(4, 3, 4.1, 3.1);
  EXPECT_TRUE(frontier_pieces(PlanningGrid(d.grid)).empty());
}

TEST(GridPlanning, DijkstraLengthsCountDiagonalsWallsAndTheirCosts) {
  Drawing d;
  d.room();
  GridPlanningOptions o;
  o.clearance_m = 0;  // no near-wall cost: plain lengths
  const PlanningGrid g(d.grid, o);
  const DistanceField f = path_lengths(g, g.cell_of({2.05, 2.05}));
  EXPECT_NEAR(length_at(g, f, {5.05, 2.05}), 3.0, 1e-9);
  EXPECT_NEAR(length_at(g, f, {4.05, 4.05}), 2.0 * std::sqrt(2.0), 1e-9);
  EXPECT_FALSE(f.reached(g.index(g.cell_of({0.95, 2.05}))));  // the wall
  EXPECT_NEAR(f.farthest_m, std::hypot(6.9, 2.9), 1e-9);      // the far corner (8.95, 4.95), in a straight line

  // A wall across the room with a gap at the top: the way round is longer.
  d.wall(5, 1, 5.1, 4.5);
  const PlanningGrid walled(d.grid, o);
  const DistanceField fw = path_lengths(walled, walled.cell_of({4.55, 2.05}));
  EXPECT_GT(length_at(walled, fw, {5.55, 2.05}), 2 * 2.4);  // up to y >= 4.5 and back down
  EXPECT_LT(length_at(walled, fw, {5.55, 2.05}), 2 * 2.4 + 1.5);

  // Near a wall each step costs near_wall_cost times more.
  GridPlanningOptions near = o;
  near.clearance_m = 0.3;
  near.near_wall_cost = 4;
  Drawing plain;
  plain.room();
  const PlanningGrid g2(plain.grid, near);
  const DistanceField f2 = path_lengths(g2, g2.cell_of({2.05, 1.05}));  // along the south wall
  // Rows 1.05-1.25 are near the south wall (4 x 0.1 m a step, 4.0 m straight along it): up two
  // rows (0.8), diagonally onto row 1.35 (0.1 sqrt 2), 9 cells along it (0.9), three rows down (1.2).
  EXPECT_NEAR(length_at(g2, f2, {3.05, 1.05}), 2.9 + 0.1 * std::sqrt(2.0), 1e-9);
}

TEST(GridPlanning, AGradedClearanceKeepsPathsToTheMiddleOfACorridor) {
  Drawing d;
  d.free(1, 2, 9, 3);  // a corridor 1 m wide, rows 2.05-2.95
  d.wall(0.9, 1.9, 9.1, 2);
  d.wall(0.9, 3, 9.1, 3.1);
  GridPlanningOptions o;
  o.clearance_m = 0.5;
  o.near_wall_cost = 3;
  o.graded_clearance = true;
  const PlanningGrid g(d.grid, o);
  // Steps cost 3x at a wall, falling linearly to 1x at 0.5 m from the wall cells' centres.
  EXPECT_NEAR(g.step_factor(g.index(g.cell_of({5.05, 2.05}))), 1 + 2 * (1 - 0.1 / 0.5), 1e-6);
  EXPECT_NEAR(g.step_factor(g.index(g.cell_of({5.05, 2.45}))), 1 + 2 * (1 - 0.5 / 0.5), 1e-6);
  EXPECT_TRUE(g.near_wall(g.index(g.cell_of({5.05, 2.35}))));
  EXPECT_FALSE(g.near_wall(g.index(g.cell_of({5.05, 2.45}))));  // 0.5 m from the south wall's cells
  // From beside one wall to beside the other 5 m on: the path crosses to the middle rows and
  // keeps there (with square marks every row of this corridor costs the same).
  const Eigen::Vector2i goal = g.cell_of({7.05, 2.85});
  const DistanceField f = path_lengths(g, g.cell_of({2.05, 2.15}), 0.5, goal);
  int middle = 0, steps = 0;
  for (const Eigen::Vector2d& p : extract_path_m(g, f, goal)) {
    ++steps;
    middle += std::abs(p.y() - 2.5) < 0.1;
  }
  EXPECT_GT(middle, steps / 2);
}

TEST(GridPlanning, UnknownCellsAreCrossedOnlyAtTheirCost) {
  Drawing d;
  d.free(1, 2, 3, 3);
  d.free(4, 2, 6, 3);  // a 1 m unknown gap between two free strips
  GridPlanningOptions o;
  o.clearance_m = 0;
  const PlanningGrid closed(d.grid, o);
  const DistanceField fc = path_lengths(closed, closed.cell_of({2.05, 2.55}));
  EXPECT_FALSE(fc.reached(closed.index(closed.cell_of({5.05, 2.55}))));
  o.unknown_cost = 3;
  const PlanningGrid open(d.grid, o);
  const DistanceField fo = path_lengths(open, open.cell_of({2.05, 2.55}));
  EXPECT_NEAR(length_at(open, fo, {5.05, 2.55}), 0.9 + 3 * 1.0 + 1.1, 1e-9);  // 10 unknown steps at 3x
}

TEST(GridPlanning, ExtractsThePathFromStartToGoal) {
  Drawing d;
  d.room();
  d.wall(5, 1, 5.1, 4.5);
  GridPlanningOptions o;
  o.clearance_m = 0;
  const PlanningGrid g(d.grid, o);
  const Eigen::Vector2i goal = g.cell_of({6.05, 2.05});
  const DistanceField f = path_lengths(g, g.cell_of({4.05, 2.05}), 0.5, goal);
  const std::vector<Eigen::Vector2d> path = extract_path_m(g, f, goal);
  ASSERT_GE(path.size(), 2u);
  EXPECT_TRUE(path.front().isApprox(Eigen::Vector2d(4.05, 2.05)));
  EXPECT_TRUE(path.back().isApprox(Eigen::Vector2d(6.05, 2.05)));
  double length = 0, top = 0;
  for (size_t i = 1; i < path.size(); ++i) {
    const double step = (path[i] - path[i - 1]).norm();
    EXPECT_LE(step, kRes * std::sqrt(2.0) + 1e-9);
    length += step;
    top = std::max(top, path[i].y());
    EXPECT_NE(g.state(g.index(g.cell_of(path[i]))), CellState::kOccupied);
  }
  EXPECT_NEAR(length, f.length_m[g.index(goal)], 1e-9);
  EXPECT_GT(top, 4.5);                                                 // over the wall's end
  EXPECT_TRUE(extract_path_m(g, f, g.cell_of({0.95, 2.05})).empty());  // a wall: not reached
}

TEST(GridPlanning, InflationBlocksCellsNearWallsAndNarrowDoors) {
  Drawing d;
  d.room();
  // A dividing wall at x = 5 with a door from y = 2 to y = 2 + door.
  auto divided = [&](double door_m) {
    Drawing w = d;
    w.wall(5, 1, 5.1, 2);
    w.wall(5, 2 + door_m, 5.1, 5);
    return w;
  };
  GridPlanningOptions o;
  o.inflation_m = 0.28;  // a 0.2 m robot plus half a cell's diagonal and a bit
  {
    const PlanningGrid g(d.grid, o);
    // The west wall's cells are at x = 0.95.
    EXPECT_TRUE(g.blocked(g.index(g.cell_of({1.05, 3.05}))));
    EXPECT_TRUE(g.blocked(g.index(g.cell_of({1.15, 3.05}))));   // 0.2 m
    EXPECT_FALSE(g.blocked(g.index(g.cell_of({1.25, 3.05}))));  // 0.3 m > 0.28
    EXPECT_TRUE(g.blocked(g.index(g.cell_of({1.15, 1.15}))));   // 0.2 m from the corner's cells
    EXPECT_FALSE(g.blocked(g.index(g.cell_of({1.25, 1.25}))));  // 0.3 m from both walls
    EXPECT_FALSE(g.traversable(g.index(g.cell_of({1.15, 3.05}))));
    EXPECT_TRUE(g.traversable(g.index(g.cell_of({1.25, 3.05}))));
  }
  const Eigen::Vector2d a(3, 3.05), b(7, 3.05);
  for (const auto& [door_m, fits] : std::vector<std::pair<double, bool>>{{0.6, true}, {0.3, false}}) {
    const Drawing w = divided(door_m);
    const PlanningGrid g(w.grid, o);
    const DistanceField f = path_lengths(g, g.cell_of(a), 0.5, g.cell_of(b));
    EXPECT_EQ(f.reached(g.index(g.cell_of(b))), fits) << "door " << door_m;
    if (fits) {
      for (const Eigen::Vector2d& p : extract_path_m(g, f, g.cell_of(b))) {
        // In the door's column and its neighbours only rows 2.25 and 2.35 are 0.28 m from both jambs.
        if (std::abs(p.x() - 5.05) < 0.15) {
          EXPECT_NEAR(p.y(), 2.3, 0.051) << "through the door's middle";
        }
      }
    }
  }
}

TEST(GridPlanning, PlansOnACoarserCopy) {
  Drawing d;
  d.room();
  d.wall(3.0, 3.0, 3.1, 3.1);  // one fine cell of rubble
  GridPlanningOptions o;
  o.cell_m = 0.2;
  const PlanningGrid g(d.grid, o);
  EXPECT_DOUBLE_EQ(g.resolution_m(), 0.2);
  // Known fine columns 9-90 (x 0.95-9.05) with 2 fine cells of margin: columns 7-92, 43 coarse cells.
  EXPECT_EQ(g.width(), 43);
  const Eigen::Vector2i rubble = g.cell_of({3.05, 3.05});
  EXPECT_EQ(g.state(g.index(rubble)), CellState::kOccupied);
  EXPECT_TRUE(g.centre_m(rubble).isApprox(Eigen::Vector2d(3.0, 3.0)));  // the 2x2 block [2.9, 3.1)
  EXPECT_EQ(g.state(g.index(g.cell_of({3.35, 3.05}))), CellState::kFree);
  o.clearance_m = 0;
  const PlanningGrid g2(d.grid, o);
  const DistanceField f = path_lengths(g2, g2.cell_of({2.2, 2.2}));
  EXPECT_NEAR(f.length_m[g2.index(g2.cell_of({5.2, 2.2}))], 3.0, 1e-9);  // 15 steps of 0.2 m
}

TEST(GridPlanning, NearestReachableFrontierGoesByPathNotByStraightLine) {
  Drawing d;
  d.room();
  d.wall(5, 1, 5.1, 4.5);          // dividing wall, passage at the top
  d.paint(5.1, 0.9, 6.1, 1, 0.f);  // east room: 1 m opening in the south wall, 1 m from the wall
  d.paint(0.9, 3.5, 1, 4.5, 0.f);  // west room: 1 m opening in the west wall
  GridPlanningOptions o;
  o.clearance_m = 0;
  const PlanningGrid g(d.grid, o);
  const std::vector<FrontierPiece> pieces = frontier_pieces(g);
  ASSERT_EQ(pieces.size(), 2u);
  const Eigen::Vector2d robot(4.5, 1.5);  // 1 m from the east opening in a straight line, 3.5 m from the west one
  const DistanceField f = path_lengths(g, g.cell_of(robot));
  std::optional<FrontierTarget> t = nearest_frontier(g, f, pieces);
  ASSERT_TRUE(t);
  EXPECT_LT(t->position_m.x(), 1.1);  // the west opening: 3.5 m of path against 2 x 3 m round the wall
  EXPECT_NEAR(t->path_m, f.length_m[g.index(t->cell)], 1e-12);
  EXPECT_LT(t->path_m, 4.5);
  // Skipping it (a blacklist) gives the east one; skipping both, nothing.
  const Eigen::Vector2d west = t->position_m;
  auto near_west = [&](const Eigen::Vector2d& p) { return (p - west).norm() < 1.5; };
  t = nearest_frontier(g, f, pieces, {}, near_west);
  ASSERT_TRUE(t);
  EXPECT_GT(t->position_m.x(), 5.1);
  EXPECT_GT(t->path_m, 6.0);
  EXPECT_FALSE(nearest_frontier(g, f, pieces, {}, [](const Eigen::Vector2d&) { return true; }));
  NearestFrontierOptions big;
  big.min_piece_cells = 11;  // both pieces have 10 cells
  EXPECT_FALSE(nearest_frontier(g, f, pieces, big));
}

TEST(GridPlanning, AStartOnAWallStartsFromTheNearestFreeCell) {
  Drawing d;
  d.room();
  const PlanningGrid g(d.grid);
  const DistanceField f = path_lengths(g, g.cell_of({0.95, 3.05}), 0.5);
  EXPECT_EQ(f.start, g.cell_of({1.05, 3.05}));
  EXPECT_TRUE(f.reached(g.index(g.cell_of({5, 3}))));
  const DistanceField none = path_lengths(g, g.cell_of({-3, 3}), 0.5);  // far outside
  EXPECT_EQ(none.start, Eigen::Vector2i(-1, -1));
  EXPECT_FALSE(none.reached(g.index(g.cell_of({5, 3}))));
}

}  // namespace
}  // namespace cairn
