#include "base_station/core/saliency_layer.h"

#include <gtest/gtest.h>

#include "base_station/core/mapper_data.h"

namespace cairn::base {
namespace {

StampNs at(double s) { return sec_to_ns(s); }

Keyframe keyframe(RobotId robot, int seq, double t_s, const SE2& T_local_base, std::vector<SalientPoint> salient = {}) {
  Keyframe kf;
  kf.id = {robot, seq};
  kf.stamp_ns = at(t_s);
  kf.T_local_base = T_local_base;
  kf.salient = std::move(salient);
  return kf;
}

TEST(SaliencyLayer, SpotsArePlacedThroughTheKeyframesGlobalPoseAndOnlyLinkedRobotsCount) {
  MapperData data;
  const RobotId a(0), b(1);
  data.starts[a] = SE2(10, 0, M_PI / 2);  // robot a's frame: origin at (10, 0), x pointing along global y
  data.keyframes[{a, 0}] = keyframe(a, 0, 1, SE2(0, 0, 0), {{4.0f, 0.0f, 0.9f}});
  data.keyframes[{b, 0}] = keyframe(b, 0, 1, SE2(0, 0, 0), {{1.0f, 1.0f, 1.0f}});  // b is not linked
  const SaliencyLayer layer = build_saliency_layer(data, at(2));
  ASSERT_FALSE(layer.empty());
  EXPECT_NEAR(layer.at({10, 4}), 0.9, 1e-6) << "4 m ahead of a robot at (10, 0) facing +y";
  EXPECT_EQ(layer.cells_above(0.1), 1);
  EXPECT_NEAR(layer.max_within({10, 6}, 2.1), 0.9, 1e-6);
  EXPECT_EQ(layer.max_within({10, 6}, 1.5), 0.0);
  EXPECT_EQ(layer.at({1, 1}), 0.0);
}

TEST(SaliencyLayer, ASpotKeepsItsWeightUntilARobotPassedCloseThenDecays) {
  MapperData data;
  const RobotId a(0);
  data.starts[a] = SE2();
  data.keyframes[{a, 0}] = keyframe(a, 0, 0, SE2(0, 0, 0), {{5.0f, 0.0f, 0.8f}});
  data.keyframes[{a, 1}] = keyframe(a, 1, 10, SE2(2, 0, 0));
  SaliencyLayerOptions o;
  o.inspected_radius_m = 1.5;
  o.decay_s = 30.0;
  EXPECT_NEAR(build_saliency_layer(data, at(100), {}, o).at({5, 0}), 0.8, 1e-6) << "nobody has been close: it keeps";
  data.keyframes[{a, 2}] = keyframe(a, 2, 40, SE2(4, 0, 0));  // 1 m from the spot at t = 40 s
  EXPECT_NEAR(build_saliency_layer(data, at(40), {}, o).at({5, 0}), 0.8, 1e-6);
  EXPECT_NEAR(build_saliency_layer(data, at(70), {}, o).at({5, 0}), 0.8 * std::exp(-1.0), 1e-6);
  EXPECT_LT(build_saliency_layer(data, at(200), {}, o).at({5, 0}), 0.01);
}

TEST(SaliencyLayer, ASpotExplainedByAFoundObjectIsLeftOut) {
  MapperData data;
  const RobotId a(0);
  data.starts[a] = SE2();
  data.keyframes[{a, 0}] = keyframe(a, 0, 0, SE2(), {{5.0f, 0.0f, 0.8f}, {5.0f, 4.0f, 0.6f}});
  const SaliencyLayer layer = build_saliency_layer(data, at(1), {{5.3, 0.2}});
  EXPECT_EQ(layer.at({5, 0}), 0.0) << "the object found there explains it";
  EXPECT_NEAR(layer.at({5, 4}), 0.6, 1e-6) << "not this one, 4 m away";
  EXPECT_TRUE(build_saliency_layer(data, at(1), {{5, 0}, {5, 4}}).empty());
}

TEST(SaliencyLayer, NothingSalientGivesAnEmptyLayer) {
  MapperData data;
  data.starts[RobotId(0)] = SE2();
  data.keyframes[{RobotId(0), 0}] = keyframe(RobotId(0), 0, 0, SE2());
  EXPECT_TRUE(build_saliency_layer(data, at(1)).empty());
  EXPECT_EQ(SaliencyLayer().max_within({0, 0}, 5.0), 0.0);
}

}  // namespace
}  // namespace cairn::base
