// Objects in both simulated worlds: recall and precision >= 90 %, mean xy error <= 0.15 m, per class.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "tests/objects/objects_sim_eval.h"

namespace cairn::agent {
namespace {

const std::string kWorlds = std::string(CAIRN_SOURCE_DIR) + "/worlds/";

// The world driven along its scripted routes (worlds/routes/<name>.yaml).
SimEvalOptions with_routes(const std::string& name) {
  SimEvalOptions options;
  options.routes_yaml = kWorlds + "routes/" + name + ".yaml";
  return options;
}

void check_world(const std::string& name) {
  const SimEvalResult r = evaluate_objects_in_world(kWorlds + name + ".yaml", with_routes(name));
  std::printf("%s:\n%s", name.c_str(), r.summary().c_str());
  for (const std::string& line : r.placed) std::printf("  %s\n", line.c_str());
  ASSERT_FALSE(r.classes.empty());
  ASSERT_EQ(r.classes.back().class_name, "all");
  // Issue #5, per class: recall and precision >= 90 %, mean xy position error <= 0.15 m (the
  // reports placed through the robot's own local SLAM and its true start, as the base would with a
  // perfect placement of the robot).
  for (const ClassScore& c : r.classes) {
    SCOPED_TRACE(name + " " + c.class_name);
    EXPECT_GT(c.ground_truth, 0);
    EXPECT_GE(c.recall(), 0.9);
    EXPECT_GE(c.precision(), 0.9);
    EXPECT_LE(c.mean_error_xy_m, 0.15);
  }
}

// The detector's own bias per object, with true robot poses. Before the box footprint fix (L-shape
// yaw, hidden sides completed) lying victims were placed 0.2-0.33 m toward the camera on average.
TEST(ObjectsSimEval, DetectorBiasWithTruePoses) {
  for (const char* name : {"office", "collapsed"}) {
    const auto bias = diagnose_detections_in_world(kWorlds + name + ".yaml", with_routes(name));
    std::printf("%s detector bias:\n%s", name, format_bias(bias).c_str());
    for (const DetectionBias& b : bias) {
      SCOPED_TRACE(std::string(name) + " object " + std::to_string(b.object_id));
      EXPECT_GE(b.detections - b.without_depth, 5);
      EXPECT_LE(std::abs(b.mean_along_ray_m), 0.1);
    }
    if (const char* id = std::getenv("CAIRN_OBJECTS_DIAG_OBJECT"))  // e.g. "collapsed/3"
      for (const DetectionBias& b : bias)
        if (std::string(name) + "/" + std::to_string(b.object_id) == id)
          for (const std::string& line : b.lines) std::printf("    %s\n", line.c_str());
  }
}

TEST(ObjectsSimEval, Office) { check_world("office"); }
TEST(ObjectsSimEval, Collapsed) { check_world("collapsed"); }

}  // namespace
}  // namespace cairn::agent
