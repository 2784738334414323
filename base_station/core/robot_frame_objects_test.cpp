// No victim hidden: a robot the base cannot place yet still shows its finds, in its own frame, told
// from where it entered; object ids stay stable when robots link and objects merge; every robot's
// time to link is kept.
#include "base_station/core/robot_frame_objects.h"

#include <gtest/gtest.h>

#include <set>

#include "base_station/core/multi_robot_mapper.h"
#include "base_station/core/object_id_registry.h"
#include "base_station/core/unlinked_robot_test_util.h"

namespace cairn::base {
namespace {

using Unlinkable = testing::UnlinkableRobot;

TEST(RobotFrameObjects, AnUnlinkedRobotsVictimIsShownInItsOwnFrameToldFromItsEntry) {
  Unlinkable u;
  ASSERT_FALSE(u.mapper.linked(RobotId(1)));
  EXPECT_TRUE(u.mapper.objects().empty()) << "nothing of robot 1 on the global map";
  const std::vector<GlobalObject> unplaced = u.mapper.unplaced_objects();
  ASSERT_EQ(unplaced.size(), 1u);
  const GlobalObject& o = unplaced[0];
  EXPECT_EQ(o.frame, RobotId(1));
  EXPECT_EQ(o.id, (ObjectId{RobotId(1), 0}));
  EXPECT_NEAR(o.position_m.x(), 4.0, 0.05);
  EXPECT_NEAR(o.position_m.y(), 0.25, 0.05);
  const FromEntry w = from_entry(u.mapper.data(), RobotId(1), o.position_m.head<2>());
  EXPECT_NEAR(w.distance_m, std::hypot(4.0, 0.25), 0.05);
  EXPECT_NEAR(w.bearing_rad, std::atan2(0.25, 4.0), 0.02);
  EXPECT_NEAR(w.path_m, 4.0, 0.05);  // its nearest keyframe is 4 m along its path
  EXPECT_EQ(describe(RobotId(1), w),
            "4.0 m from where robot 1 entered, 4 deg left of its heading there (4 m along its path)");
  // The merged view carries it and robot 1's own map.
  const MergedMap merged = u.mapper.merged();
  ASSERT_EQ(merged.unplaced_objects.size(), 1u);
  ASSERT_EQ(merged.robot_frame_maps->size(), 1u);
  EXPECT_EQ((*merged.robot_frame_maps)[0].robot, RobotId(1));
  EXPECT_GT((*merged.robot_frame_maps)[0].grid.known_area_m2(), 5.0);
  EXPECT_EQ((*merged.robot_frame_maps)[0].trajectory.size(), u.corridor.size());
  EXPECT_EQ((*merged.robot_frame_maps)[0].objects.size(), 1u);
}

TEST(RobotFrameObjects, TimeToLinkIsKeptPerRobot) {
  Unlinkable u;
  for (const RobotSummary& r : u.mapper.robots()) {
    if (r.id == RobotId(0)) EXPECT_EQ(r.time_to_link_s, 0.0) << "the anchor is linked from its first keyframe";
    if (r.id == RobotId(1)) EXPECT_EQ(r.time_to_link_s, -1.0) << "never linked";
  }
}

GlobalObject merged_of(std::vector<ObjectId> reports) {
  GlobalObject o;
  std::sort(reports.begin(), reports.end());
  o.reports = reports;
  o.id = reports.front();  // as merge_object_reports names it
  return o;
}

TEST(ObjectIdRegistry, AnObjectKeepsTheIdItWasFirstShownUnderWhenItMerges) {
  const ObjectId r0{RobotId(0), 2}, r1{RobotId(1), 3}, r2{RobotId(2), 0};
  ObjectIdRegistry ids;
  std::vector<GlobalObject> first = {merged_of({r1})};  // robot 1's victim, shown first
  ids.assign(&first);
  EXPECT_EQ(first[0].id, r1);
  std::vector<GlobalObject> second = {merged_of({r1}), merged_of({r0})};
  ids.assign(&second);
  EXPECT_EQ(second[0].id, r0);
  EXPECT_EQ(second[1].id, r1);
  // Robot 1 links; both reports are one victim: it stays "1-3", "0-2" becomes its alias.
  std::vector<GlobalObject> merged = {merged_of({r0, r1})};
  ids.assign(&merged);
  EXPECT_EQ(merged[0].id, r1);
  EXPECT_EQ(merged[0].aliases, std::vector<ObjectId>{r0});
  ids.assign(&merged);  // the next refresh: "0-2" is still its alias (it was lost after one second)
  EXPECT_EQ(merged[0].id, r1);
  EXPECT_EQ(merged[0].aliases, std::vector<ObjectId>{r0});
  // The merge no longer holds: one part keeps "1-3", the other gets back "0-2"; a new one its own.
  std::vector<GlobalObject> split = {merged_of({r0}), merged_of({r1}), merged_of({r2})};
  ids.assign(&split);
  ASSERT_EQ(split.size(), 3u);
  EXPECT_EQ(split[0].id, r0);
  EXPECT_EQ(split[1].id, r1);
  EXPECT_EQ(split[2].id, r2);
  for (const GlobalObject& o : split) EXPECT_TRUE(o.aliases.empty());
}

TEST(ObjectIdRegistry, ARestartedBaseShowsAMergedVictimUnderTheIdTheTeamAlreadyKnows) {
  // Robot 1's victim was shown first as "1-3"; robot 0's report of it came later and merged. A base
  // restarted from its journal computes the merged object at once: without the journaled facts it
  // would name it after its smallest report, "0-2".
  const ObjectId r0{RobotId(0), 2}, r1{RobotId(1), 3};
  ObjectIdRegistry before;
  std::vector<GlobalObject> first = {merged_of({r1})};
  before.assign(&first);
  std::vector<GlobalObject> merged = {merged_of({r0, r1})};
  before.assign(&merged);
  ASSERT_EQ(merged[0].id, r1);
  const std::vector<ObjectIdRegistry::Entry> journaled = before.take_new_entries();
  ASSERT_EQ(journaled.size(), 2u);  // r1 shown as r1, then r0 shown as r1
  EXPECT_TRUE(before.take_new_entries().empty());

  ObjectIdRegistry forgetful;
  std::vector<GlobalObject> at_once = {merged_of({r0, r1})};
  forgetful.assign(&at_once);
  EXPECT_EQ(at_once[0].id, r0);  // what a restart did before the registry was journaled

  ObjectIdRegistry restarted;
  for (const auto& e : journaled) ASSERT_TRUE(restarted.restore(e));
  std::vector<GlobalObject> again = {merged_of({r0, r1})};
  restarted.assign(&again);
  EXPECT_EQ(again[0].id, r1);
  EXPECT_TRUE(restarted.take_new_entries().empty());  // nothing new learnt: nothing to journal again
  // A fact that contradicts the restored order is refused.
  EXPECT_FALSE(restarted.restore({ObjectId{RobotId(2), 0}, ObjectId{RobotId(2), 0}, journaled.front().order}));
}

TEST(ObjectIdRegistry, EveryIdTheTeamSawStaysFindableThroughARestartThatSplitsAndMergesAgain) {
  // A CI run of the demo: an exit was shown as "1-2", merged with robot 0's "0-5" into an older
  // object, split off from it again under "0-5"; the base restarted from its journal saw the two
  // reports apart first (their robots not linked yet), then merged: "0-5" was gone.
  const ObjectId r05{RobotId(0), 5}, r12{RobotId(1), 2}, r21{RobotId(2), 1};
  ObjectIdRegistry live;
  std::vector<GlobalObject> step = {merged_of({r21})};
  live.assign(&step);
  step = {merged_of({r21}), merged_of({r12})};
  live.assign(&step);
  step = {merged_of({r05, r12, r21})};
  live.assign(&step);
  step = {merged_of({r05, r12}), merged_of({r21})};  // the split: r21 keeps "2-1"
  live.assign(&step);
  std::set<ObjectId> known;
  for (const GlobalObject& o : step) {
    known.insert(o.id);
    known.insert(o.aliases.begin(), o.aliases.end());
  }
  EXPECT_EQ(known, (std::set<ObjectId>{r05, r12, r21}));

  ObjectIdRegistry restarted;
  for (const auto& e : live.take_new_entries()) ASSERT_TRUE(restarted.restore(e));
  std::vector<GlobalObject> apart = {merged_of({r05}), merged_of({r12}), merged_of({r21})};
  restarted.assign(&apart);
  std::vector<GlobalObject> again = {merged_of({r05, r12}), merged_of({r21})};
  restarted.assign(&again);
  restarted.assign(&again);
  std::set<ObjectId> after;
  for (const GlobalObject& o : again) {
    EXPECT_TRUE(after.insert(o.id).second) << to_string(o.id) << " twice";
    for (ObjectId a : o.aliases) EXPECT_TRUE(after.insert(a).second) << to_string(a) << " twice";
  }
  EXPECT_EQ(after, known);
}

}  // namespace
}  // namespace cairn::base
