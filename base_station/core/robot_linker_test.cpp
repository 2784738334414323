// RobotLinker on its own, over MapperData (no pose graph): note_keyframe() decides nothing beyond
// the provisional anchor, update() makes every link decision and says what changed.
#include "base_station/core/robot_linker.h"

#include <gtest/gtest.h>

#include "base_station/core/synthetic_world_test_util.h"

namespace cairn::base {
namespace {

std::vector<SE2> path() { return testing::long_path(); }
std::vector<SE2> retraced() { return testing::retrace(testing::long_path()); }

void store(const std::vector<Keyframe>& keyframes, RobotLinker* linker, MapperData* data) {
  for (const Keyframe& kf : keyframes) {
    data->keyframes.emplace(kf.id, kf);
    linker->note_keyframe(kf, data);
  }
}

TEST(RobotLinker, NotingKeyframesDecidesNothingButTheProvisionalAnchor) {
  RobotLinker linker;
  MapperData data;
  const auto walls = testing::room_walls();
  store(testing::make_keyframes(RobotId(1), retraced(), walls), &linker, &data);
  EXPECT_EQ(data.anchor, RobotId(1));  // the lowest robot seen so far, provisionally
  store(testing::make_keyframes(RobotId(0), path(), walls), &linker, &data);
  EXPECT_EQ(data.anchor, RobotId(0));  // a lower id took over before the first update
  EXPECT_TRUE(data.linked(RobotId(0)));
  EXPECT_FALSE(data.linked(RobotId(1)));
  EXPECT_TRUE(data.loops.empty()) << "no closure is accepted before update()";
  EXPECT_EQ(linker.stats().hypotheses, 0);
}

TEST(RobotLinker, UpdateLinksAndPlacesTheSecondRobotAndSaysSo) {
  RobotLinker linker;
  MapperData data;
  const auto walls = testing::room_walls();
  const std::vector<SE2> p0 = path(), p1 = retraced();
  store(testing::make_keyframes(RobotId(0), p0, walls), &linker, &data);
  store(testing::make_keyframes(RobotId(1), p1, walls), &linker, &data);
  const LinkUpdate update = linker.update(&data);
  ASSERT_EQ(update.newly_linked, std::vector<RobotId>{RobotId(1)});
  EXPECT_TRUE(update.full_resolve);
  EXPECT_TRUE(update.placements_changed);
  ASSERT_FALSE(update.events.empty());
  EXPECT_TRUE(update.events.back().accepted) << update.events.back().reason;
  EXPECT_EQ(linker.stats().linked, 1);
  ASSERT_TRUE(data.linked(RobotId(1)));
  EXPECT_FALSE(data.loops.empty());
  // Robot 1's start in the global frame (robot 0's local frame) from the closures alone.
  const SE2 truth = p0[0].inverse() * p1[0];
  const SE2 start = data.starts.at(RobotId(1));
  EXPECT_LT((start.translation() - truth.translation()).norm(), 0.05);
  EXPECT_LT(std::abs(start.between(truth).yaw()), 0.02);
  // Nothing new: a second update decides nothing more.
  const LinkUpdate again = linker.update(&data);
  EXPECT_TRUE(again.newly_linked.empty());
  EXPECT_FALSE(again.full_resolve);
}

}  // namespace
}  // namespace cairn::base
