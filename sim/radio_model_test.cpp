#include "sim/radio_model.h"

#include <gtest/gtest.h>

#include <cmath>

namespace cairn::sim {
namespace {

// 20 m x 5 m at 0.05 m with wall columns at x = 5, 10 and 15 m (one cell thick, 3 cells at 15 m).
FloorPlan three_walls() {
  std::vector<uint8_t> cells(400 * 100, 0);
  for (int r = 0; r < 100; ++r) {
    for (int c : {100, 200, 300, 301, 302}) cells[size_t(r) * 400 + size_t(c)] = 1;
  }
  return FloorPlan(400, 100, 0.05, Eigen::Vector2d(0, 0), cells);
}

RadioOptions one_antenna_at(const Eigen::Vector2d& p) {
  RadioOptions o;
  o.antennas_m = {p};
  return o;
}

TEST(RadioModel, CountsEachWallCrossedOnceWhateverItsThickness) {
  const FloorPlan plan = three_walls();
  EXPECT_EQ(walls_crossed(plan, {1, 2.5}, {4, 2.5}), 0);
  EXPECT_EQ(walls_crossed(plan, {1, 2.5}, {7, 2.5}), 1);
  EXPECT_EQ(walls_crossed(plan, {1, 2.5}, {19, 1.0}), 3);  // the 15 cm wall counts once
  EXPECT_EQ(walls_crossed(plan, {19, 1.0}, {1, 2.5}), 3);  // the same both ways
}

TEST(RadioModel, ReceivedPowerFollowsTheMultiWallModel) {
  const FloorPlan plan = three_walls();
  const RadioOptions o = one_antenna_at({1, 2.5});
  // 3.9 m in the open: 15 - 40 - 20 log10(3.9) dBm.
  EXPECT_NEAR(radio_reading(plan, o, {4.9, 2.5}).received_dbm, 15 - 40 - 20 * std::log10(3.9), 1e-9);
  const RadioReading far = radio_reading(plan, o, {19, 2.5});
  EXPECT_EQ(far.walls, 3);
  EXPECT_NEAR(far.received_dbm, 15 - 40 - 20 * std::log10(18.0) - 3 * 10, 1e-9);
  // Closer than the 1 m reference distance gains nothing.
  EXPECT_NEAR(radio_reading(plan, o, {1.2, 2.5}).received_dbm, 15 - 40, 1e-9);
}

TEST(RadioModel, ARobotHearsTheBaseThroughItsBestAntenna) {
  const FloorPlan plan = three_walls();
  RadioOptions o = one_antenna_at({1, 2.5});
  o.antennas_m.push_back({18, 2.5});
  const RadioReading r = radio_reading(plan, o, {19, 2.5});
  EXPECT_EQ(r.walls, 0);
  EXPECT_NEAR(r.received_dbm, 15 - 40, 1e-9);
  EXPECT_TRUE(std::isinf(radio_reading(plan, RadioOptions{}, {1, 1}).received_dbm));  // no antenna: no link
}

TEST(RadioModel, ALinkIsCutBelowTheSensitivityAndBackOnlyAfterStayingAboveTheHysteresis) {
  RadioOptions o;
  o.sensitivity_dbm = -80;
  o.hysteresis_db = 3;
  o.reconnect_s = 2;
  RadioLink link(o);
  auto at = [](double t_s) { return sec_to_ns(t_s); };
  EXPECT_TRUE(link.up());
  EXPECT_FALSE(link.update({-79.9, 0}, at(0)));
  EXPECT_TRUE(link.update({-80.1, 0}, at(1)));  // cut
  EXPECT_FALSE(link.up());
  EXPECT_FALSE(link.update({-78.0, 0}, at(2)));  // within the hysteresis: still cut
  EXPECT_FALSE(link.update({-77.0, 0}, at(3)));  // good enough, not for long enough yet
  EXPECT_FALSE(link.update({-90.0, 0}, at(4)));  // faded again: the wait starts over
  EXPECT_FALSE(link.update({-70.0, 0}, at(5)));
  EXPECT_FALSE(link.update({-70.0, 0}, at(6)));
  EXPECT_FALSE(link.up());
  EXPECT_TRUE(link.update({-70.0, 0}, at(7)));  // 2 s in range: back
  EXPECT_TRUE(link.up());
}

TEST(RadioModel, LinksAreSampledEveryPeriodAndAWalkBehindWallsCutsThem) {
  const FloorPlan plan = three_walls();
  RadioOptions o = one_antenna_at({1, 2.5});
  o.sensitivity_dbm = -80;  // b 3 m away in the open: -34.5 dBm; 18 m away behind three walls: -80.1 dBm
  o.period_s = 0.5;
  RadioLinks links(plan, o);
  const RobotId a{0}, b{1};
  auto at = [&](double t_s, double xb) {
    return links.update(sec_to_ns(t_s), {{a, Eigen::Vector2d(2, 2.5)}, {b, Eigen::Vector2d(xb, 2.5)}});
  };
  const auto first = at(0.0, 4);
  ASSERT_EQ(first.size(), 2u);
  EXPECT_TRUE(first[0].up && first[1].up);
  EXPECT_TRUE(at(0.2, 19).empty());  // not due yet
  const auto cut = at(0.5, 19);
  ASSERT_EQ(cut.size(), 2u);
  EXPECT_EQ(cut[1].robot, b);
  EXPECT_FALSE(cut[1].up);
  EXPECT_TRUE(cut[1].changed);
  EXPECT_TRUE(cut[0].up);
  EXPECT_FALSE(cut[0].changed);
  EXPECT_FALSE(at(1.0, 8)[1].up);  // in range again, reconnecting
  EXPECT_FALSE(at(1.5, 8)[1].up);
  EXPECT_FALSE(at(2.0, 8)[1].up);
  const auto back = at(3.0, 8);  // 2 s after it came in range
  EXPECT_TRUE(back[1].up && back[1].changed);
}

}  // namespace
}  // namespace cairn::sim
