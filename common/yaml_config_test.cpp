#include "common/yaml_config.h"

#include <gtest/gtest.h>

#include <functional>

namespace cairn {
namespace {

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(YamlConfig, ReadsValuesDefaultsAndSequences) {
  auto cfg = YamlConfig::from_string("laser: {beams: 360, noise_m: 0.01}\nrobots: [{id: 0}, {id: 1}]\n", "t.yaml");
  EXPECT_EQ(cfg["laser"].require<int>("beams"), 360);
  EXPECT_DOUBLE_EQ(cfg["laser"].get("noise_m", 0.5), 0.01);
  EXPECT_DOUBLE_EQ(cfg["laser"].get("missing_m", 0.5), 0.5);
  auto robots = cfg.sequence("robots");
  ASSERT_EQ(robots.size(), 2u);
  EXPECT_EQ(robots[1].require<int>("id"), 1);
}

TEST(YamlConfig, ErrorsNameFileAndKey) {
  auto cfg = YamlConfig::from_string("laser: {beams: many, range: .nan}\nrobots: [{id: 0}]\n", "w.yaml");
  EXPECT_EQ(error_of([&] { cfg["laser"].require<int>("beams"); }).rfind("w.yaml: key 'laser.beams'", 0), 0u);
  EXPECT_NE(error_of([&] { cfg["laser"].require<double>("range"); }).find("finite"), std::string::npos);
  EXPECT_NE(error_of([&] { cfg["camera"]; }).find("'camera' is missing"), std::string::npos);
  EXPECT_NE(error_of([&] { cfg.sequence("robots")[0].require<int>("start"); }).find("robots[0].start"),
            std::string::npos);
  EXPECT_NE(error_of([] { YamlConfig::from_string("a: [1, 2\n", "bad.yaml"); }).find("bad.yaml: malformed YAML"),
            std::string::npos);
  auto typo = YamlConfig::from_string("map: {resolutoin_m: 0.05, image: a.pgm}\n", "t.yaml");
  EXPECT_NE(error_of([&] {
              typo["map"].allow_only({"image", "resolution_m"});
            }).find("t.yaml: key 'map.resolutoin_m' is not a known key (expected one of: image, resolution_m)"),
            std::string::npos);
  EXPECT_NE(error_of([] { YamlConfig::load("/nonexistent/x.yaml"); }).find("cannot open"), std::string::npos);
}

}  // namespace
}  // namespace cairn
