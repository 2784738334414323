#include "tools/eval/coverage_eval.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "common/errors.h"
#include "common/occupancy_grid.h"

namespace cairn::eval {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("cairn_coverage_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// Truth: a 4 m x 2 m explorable strip at 0.05 m (x in [0, 4), y in [0, 2)).
void write_truth(const fs::path& dir) {
  std::ofstream pgm(dir / "gt_reachable.pgm", std::ios::binary);
  pgm << "P5\n80 40\n255\n";
  for (int i = 0; i < 80 * 40; ++i) pgm.put(char(255));
  std::ofstream(dir / "gt_reachable.yaml") << "image: gt_reachable.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n";
}

TEST(CoverageEval, TheShareOfTheExplorableAreaObservedOnTheMap) {
  const fs::path gt = fresh_dir("gt"), map = fresh_dir("map");
  write_truth(gt);
  // The map saw the left half (x < 2 m) as free: a fan of beams from (1, 1) ending beyond it.
  OccupancyGrid grid;
  grid.reserve({-1, -1}, {5, 3});
  for (int i = 0; i < 20; ++i) {
    for (double y = 0.01; y < 2.0; y += 0.02) {
      grid.insert_scan(SE2(0.0, y, 0.0), {}, {Eigen::Vector2f(2.0f, 0.f)});
    }
  }
  ASSERT_TRUE(grid.write_pgm_yaml((map / "map").string()));
  const auto c = evaluate_coverage(gt.string(), map.string());
  ASSERT_TRUE(c);
  EXPECT_NEAR(c->reachable_m2, 8.0, 1e-9);
  EXPECT_NEAR(c->covered_m2, 4.0, 0.15);
  EXPECT_NEAR(c->fraction(), 0.5, 0.02);
  // Laid over the truth by T_world_map (its frame 1 m behind the world's along x), what it saw
  // covers only the truth's x in [0, 1): a quarter.
  const auto off = evaluate_coverage(gt.string(), map.string(), SE2(-1.0, 0.0, 0.0));
  ASSERT_TRUE(off);
  EXPECT_NEAR(off->fraction(), 0.25, 0.02);
  const auto back = evaluate_coverage(gt.string(), map.string(), SE2(0.0, 0.0, 0.0));
  EXPECT_NEAR(back->fraction(), c->fraction(), 1e-12);
}

TEST(CoverageEval, AbsentTruthGivesNoScoreAndABadImageIsNamed) {
  const fs::path gt = fresh_dir("gt2"), map = fresh_dir("map2");
  EXPECT_FALSE(evaluate_coverage(gt.string(), map.string()));
  write_truth(gt);
  std::ofstream(gt / "gt_reachable.pgm") << "P2\n1 1\n255\n0\n";
  try {
    evaluate_coverage(gt.string(), map.string());
    FAIL() << "a P2 image must be refused";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("gt_reachable.pgm: not a binary PGM"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace cairn::eval
