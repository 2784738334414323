#include "tools/mission/exploration_report.h"

#include <gtest/gtest.h>

#include <filesystem>

namespace cairn::mission {
namespace {

TEST(ExplorationReport, CoveragePerSecondTimesToThresholdsAndVictims) {
  // The live observed area grows to 200 m2; the final map was scored at 100 % coverage.
  const nlohmann::json series = nlohmann::json::parse(R"([
    {"t_s": 0.5, "known_m2": 20, "victims": 0},
    {"t_s": 2.5, "known_m2": 110, "victims": 1},
    {"t_s": 4.2, "known_m2": 190, "victims": 1},
    {"t_s": 6.0, "known_m2": 200, "victims": 2}])");
  const ExplorationFigures f = exploration_figures(series, 1.0, 2, 7.0);
  ASSERT_EQ(f.per_second.size(), 8u);  // 0..7 s
  EXPECT_DOUBLE_EQ(f.per_second[0]["coverage"].get<double>(), 0.0);
  EXPECT_DOUBLE_EQ(f.per_second[2]["coverage"].get<double>(), 0.10);
  EXPECT_DOUBLE_EQ(f.per_second[3]["coverage"].get<double>(), 0.55);
  ASSERT_TRUE(f.t50_s && f.t90_s && f.t99_s && f.all_victims_s);
  EXPECT_EQ(*f.t50_s, 3);
  EXPECT_EQ(*f.t90_s, 5);
  EXPECT_EQ(*f.t99_s, 6);
  EXPECT_EQ(*f.all_victims_s, 6);
  EXPECT_DOUBLE_EQ(f.final_coverage, 1.0);
  const ExplorationFigures none = exploration_figures(series, 0.5, 3, 7.0);
  EXPECT_FALSE(none.t90_s);
  EXPECT_FALSE(none.all_victims_s);
  const std::string png = (std::filesystem::temp_directory_path() / "cairn_coverage_plot.png").string();
  std::filesystem::remove(png);
  ASSERT_TRUE(write_coverage_plot({{"coordinated", f.per_second}, {"nearest", none.per_second}}, 2, "test", png));
  EXPECT_GT(std::filesystem::file_size(png), 2000u);
  EXPECT_FALSE(write_coverage_plot({{"x", f.per_second}}, 2, "test", "/nonexistent-dir/x.png"));
}

}  // namespace
}  // namespace cairn::mission
