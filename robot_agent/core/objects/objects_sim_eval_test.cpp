// Objects in both simulated worlds: recall and precision >= 90 %, mean xy error <= 0.15 m.
#include <gtest/gtest.h>

#include "robot_agent/core/objects/objects_sim_eval.h"

namespace cairn::agent {
namespace {

void check_world(const std::string& name) {
  const SimEvalResult r = evaluate_objects_in_world(std::string(CAIRN_SOURCE_DIR) + "/worlds/" + name + ".yaml");
  std::printf("%s:\n%s", name.c_str(), r.summary().c_str());
  for (const std::string& line : r.placed) std::printf("  %s\n", line.c_str());
  ASSERT_FALSE(r.classes.empty());
  const ClassScore& all = r.classes.back();
  EXPECT_GE(all.recall(), 0.9);
  EXPECT_GE(all.precision(), 0.9);
  EXPECT_LE(all.mean_error_xy_m, 0.15);
}

TEST(ObjectsSimEval, Office) { check_world("office"); }
TEST(ObjectsSimEval, Collapsed) { check_world("collapsed"); }

}  // namespace
}  // namespace cairn::agent
