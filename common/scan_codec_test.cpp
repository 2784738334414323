#include "common/scan_codec.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/cloud_codec.h"

namespace cairn {
namespace {

TEST(ScanCodec, RoundTripQuantisesToAMillimetreAndKeepsNoReturns) {
  LaserScan s;
  s.angle_min_rad = -1.5f;
  s.angle_increment_rad = 0.01f;
  s.range_max_m = 30.f;
  for (int i = 0; i < 361; ++i) s.ranges_m.push_back(0.5f + 0.0123f * i);
  s.ranges_m[10] = std::nanf("");
  s.ranges_m[11] = 40.f;
  const auto bytes = encode_scan(s);
  EXPECT_LT(bytes.size(), 361u * 2);
  std::string error;
  auto back = decode_scan(bytes, &error);
  ASSERT_TRUE(back) << error;
  EXPECT_FLOAT_EQ(back->angle_min_rad, -1.5f);
  EXPECT_NEAR(back->ranges_m[100], s.ranges_m[100], 5e-4);
  EXPECT_EQ(back->ranges_m[10], 0.f);
  EXPECT_TRUE(std::isinf(back->ranges_m[11]));
}

TEST(ScanCodec, CorruptBytesGiveAnErrorNotACrash) {
  LaserScan s;
  s.ranges_m.assign(100, 1.f);
  auto bytes = encode_scan(s);
  std::string error;
  auto truncated = bytes;
  truncated.resize(bytes.size() / 2);
  EXPECT_FALSE(decode_scan(truncated, &error));
  EXPECT_FALSE(error.empty());
  EXPECT_FALSE(decode_scan({}, &error));
  std::vector<uint8_t> garbage(64, 0xAB);
  EXPECT_FALSE(decode_scan(garbage, &error));
}

TEST(CloudCodec, RoundTripAndCompression) {
  ColoredCloud cloud;
  for (int i = 0; i < 2000; ++i) {
    cloud.push_back({0.001f * (i % 400), 0.002f * (i / 400), 0.3f, uint8_t(200), uint8_t(i % 7), 20});
  }
  const auto bytes = encode_cloud(cloud);
  EXPECT_LT(bytes.size(), cloud.size() * 15 / 2);  // at least 2x smaller than float xyz + rgb
  std::string error;
  auto back = decode_cloud(bytes, &error);
  ASSERT_TRUE(back) << error;
  ASSERT_EQ(back->size(), cloud.size());
  EXPECT_NEAR((*back)[777].x, cloud[777].x, 6e-4);
  EXPECT_EQ((*back)[777].g, cloud[777].g);
  auto bad = bytes;
  bad.resize(5);
  EXPECT_FALSE(decode_cloud(bad, &error));
}

}  // namespace
}  // namespace cairn
