#include "base_station/core/object_verdicts.h"

#include <gtest/gtest.h>

namespace cairn::base {
namespace {

TEST(ObjectVerdicts, AMergedObjectTakesTheNewestVerdictGivenUnderAnyOfItsIds) {
  const ObjectId a{RobotId(0), 2}, b{RobotId(1), 0}, c{RobotId(1), 5};
  ObjectVerdicts verdicts;
  verdicts.set({a, ObjectVerdict::kConfirmed, "moving, calls for help", sec_to_ns(10)});
  verdicts.set({b, ObjectVerdict::kFalse, "a red jacket", sec_to_ns(20)});
  std::vector<GlobalObject> objects(3);
  objects[0].id = a;  // judged, on its own
  objects[1].id = a;  // later merged with b: b's verdict is newer
  objects[1].aliases = {b};
  objects[2].id = c;  // never judged
  objects[2].reports = {c};
  verdicts.apply(&objects);
  EXPECT_EQ(objects[0].verdict, ObjectVerdict::kConfirmed);
  EXPECT_EQ(objects[0].verdict_note, "moving, calls for help");
  EXPECT_EQ(objects[1].verdict, ObjectVerdict::kFalse);
  EXPECT_EQ(objects[1].verdict_note, "a red jacket");
  EXPECT_EQ(objects[2].verdict, ObjectVerdict::kUnreviewed);
  // A new word under the same id replaces the old one.
  verdicts.set({a, ObjectVerdict::kUnreviewed, "", sec_to_ns(30)});
  verdicts.apply(&objects);
  EXPECT_EQ(objects[1].verdict, ObjectVerdict::kUnreviewed);
  EXPECT_EQ(verdicts.records().size(), 2u);
}

}  // namespace
}  // namespace cairn::base
