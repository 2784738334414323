#include "robot_agent/app/agent_config.h"

#include <gtest/gtest.h>

#include <fstream>

#include "common/errors.h"

namespace cairn::agent {
namespace {

std::string write_file(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

TEST(AgentConfig, ReadsKeyframerAndSwitches) {
  const auto path = write_file("agent_ok.yaml",
                               "keyframer: {min_distance_m: 0.8, min_angle_deg: 30, max_interval_s: 4}\n"
                               "odometry: {use: false}\nobjects: {enabled: false}\n");
  const AgentOptions o = load_agent_options(path);
  EXPECT_DOUBLE_EQ(o.keyframer.min_distance_m, 0.8);
  EXPECT_NEAR(o.keyframer.min_angle_rad, 30 * M_PI / 180, 1e-12);
  EXPECT_FALSE(o.use_odometry);
  EXPECT_FALSE(o.enable_objects);
}

TEST(AgentConfig, ReadsTheOdometryNoiseForARobotWithoutLaser) {
  const AgentOptions o = load_agent_options(
      write_file("agent_odo.yaml",
                 "odometry: {laser_timeout_s: 2.5, translation_variance_m2_per_m: 0.01, rotation_variance_rad2_per_m: "
                 "0.001, rotation_variance_rad2_per_rad: 0.004, dead_reckon_without_laser: true}\n"));
  EXPECT_TRUE(o.dead_reckon_without_laser);
  EXPECT_DOUBLE_EQ(o.dead_reckoning.laser_timeout_s, 2.5);
  EXPECT_DOUBLE_EQ(o.dead_reckoning.translation_variance_m2_per_m, 0.01);
  EXPECT_DOUBLE_EQ(o.dead_reckoning.rotation_variance_rad2_per_m, 0.001);
  EXPECT_DOUBLE_EQ(o.dead_reckoning.rotation_variance_rad2_per_rad, 0.004);
  for (const std::string bad : {"laser_timeout_s: 0", "translation_variance_m2_per_m: -0.1",
                                "rotation_variance_rad2_per_rad: .nan", "rotation_variance_rad2_per_m: 5"}) {
    try {
      load_agent_options(write_file("agent_odo_bad.yaml", "odometry: {" + bad + "}\n"));
      ADD_FAILURE() << bad;
    } catch (const InputError& e) {
      const std::string key = "odometry." + bad.substr(0, bad.find(':'));
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  }
}

TEST(AgentConfig, BadValuesNameTheKey) {
  const auto path = write_file("agent_bad.yaml", "keyframer: {min_distance_m: -1}\n");
  try {
    load_agent_options(path);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("keyframer.min_distance_m"), std::string::npos) << e.what();
  }
  EXPECT_THROW(load_agent_options(write_file("agent_type.yaml", "odometry: {use: maybe}\n")), InputError);
  EXPECT_THROW(load_agent_options("/nonexistent/agent.yaml"), InputError);
  EXPECT_THROW(load_agent_options(write_file("agent_typo.yaml", "keyframer: {min_distance: 1}\n")), InputError);
}

TEST(AgentConfig, TeammateTapeIsOffForARos2LaserUnlessGiven) {
  EXPECT_FLOAT_EQ(teammate_min_intensity(std::nullopt, false, 0.9f), 0.9f) << "the simulator's 0-1 scale";
  EXPECT_FLOAT_EQ(teammate_min_intensity(std::nullopt, true, 0.9f), 0.f) << "a real laser's own units";
  EXPECT_FLOAT_EQ(teammate_min_intensity(3000.f, true, 0.9f), 3000.f);
  EXPECT_FLOAT_EQ(teammate_min_intensity(0.f, false, 0.9f), 0.f);
}

}  // namespace
}  // namespace cairn::agent
