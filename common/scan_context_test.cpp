#include "common/scan_context.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

namespace cairn {
namespace {

/// Points of an L-shaped room corner seen from the origin, rotated by yaw (as seen by a sensor
/// rotated by -yaw... i.e. a sensor with yaw `sensor_yaw` sees world points rotated by -sensor_yaw).
std::vector<Eigen::Vector2f> scene(double sensor_yaw, std::mt19937* rng) {
  std::vector<Eigen::Vector2f> world;
  for (double t = -6; t <= 6; t += 0.05) {
    world.emplace_back(float(t), 4.f);
    world.emplace_back(-3.f, float(t));
    if (t > 0) world.emplace_back(float(t), -2.f - 0.3f * float(t));
  }
  std::normal_distribution<float> n(0.f, 0.01f);
  const Eigen::Rotation2Df R(float(-sensor_yaw));
  std::vector<Eigen::Vector2f> out;
  for (const auto& p : world) out.push_back(R * p + Eigen::Vector2f(n(*rng), n(*rng)));
  return out;
}

TEST(ScanContext, RotationInvariantWithYawEstimate) {
  std::mt19937 rng(1);
  const std::vector<float> a = compute_scan_context(scene(0.0, &rng));
  const std::vector<float> b = compute_scan_context(scene(1.2, &rng));
  const ScanContextMatch m = scan_context_distance(a, b);
  ASSERT_TRUE(m.valid);
  EXPECT_LT(m.distance, 0.15);
  EXPECT_NEAR(m.yaw_rad, 1.2, 2 * 2 * M_PI / 60);
  const auto ka = scan_context_ring_key(a), kb = scan_context_ring_key(b);
  for (size_t r = 0; r < ka.size(); ++r) EXPECT_NEAR(ka[r], kb[r], 0.15);
}

TEST(ScanContext, DifferentPlacesAreFar) {
  std::mt19937 rng(2);
  std::vector<Eigen::Vector2f> corridor;
  for (double t = -15; t <= 15; t += 0.05) {
    corridor.emplace_back(float(t), 1.0f);
    corridor.emplace_back(float(t), -1.0f);
  }
  const ScanContextMatch m =
      scan_context_distance(compute_scan_context(scene(0, &rng)), compute_scan_context(corridor));
  EXPECT_GT(m.distance, 0.3);
  EXPECT_TRUE(compute_scan_context(std::vector<Eigen::Vector2f>{}).empty());
}

Keyframe keyframe_at(RobotId robot, int32_t seq, const SE2& pose, float range) {
  Keyframe kf;
  kf.id = KeyframeId{robot, seq};
  kf.T_local_base = pose;
  kf.scan.angle_min_rad = float(-M_PI / 2);
  kf.scan.angle_increment_rad = float(M_PI / 180);
  kf.scan.ranges_m.assign(181, range);
  return kf;
}

TEST(ScanContext, KeyframeDescriptorMergesRecentPredecessorsInItsFrame) {
  const Keyframe k0 = keyframe_at(RobotId(1), 4, SE2(0, 0, 0), 3.f);
  const Keyframe k1 = keyframe_at(RobotId(1), 5, SE2(1, 0, 0.5), 5.f);
  const Keyframe k2 = keyframe_at(RobotId(1), 6, SE2(2, 1, 1.0), 7.f);
  const Keyframe old = keyframe_at(RobotId(1), 3, SE2(5, 5, 0), 9.f);    // too far back (3 keyframes)
  const Keyframe other = keyframe_at(RobotId(2), 5, SE2(0, 0, 0), 9.f);  // another robot
  std::vector<Eigen::Vector2f> expected;
  for (const Keyframe* k : {&k2, &k1, &k0}) {
    const SE2 T = k2.T_local_base.between(k->T_local_base);
    for (const Eigen::Vector2f& p : scan_to_points(k->scan)) expected.push_back((T * p.cast<double>()).cast<float>());
  }
  ScanContextOptions three;
  three.descriptor_keyframes = 3;
  const std::vector<float> d = compute_keyframe_scan_context(k2, {&old, &k0, &other, &k1}, three);
  EXPECT_EQ(d, compute_scan_context(expected, three));
  EXPECT_TRUE(scan_context_size_ok(d));
  EXPECT_EQ(compute_keyframe_scan_context(k2, {}), compute_scan_context(k2.scan));
}

}  // namespace
TEST(ScanContextCodec, RoundTripIsCompactAndCloseAndCorruptBytesFail) {
  LaserScan scan;
  scan.angle_min_rad = float(-M_PI);
  scan.angle_increment_rad = float(2 * M_PI / 360);
  scan.range_max_m = 30.f;
  for (int i = 0; i < 360; ++i) scan.ranges_m.push_back(3.f + 2.f * std::sin(i * 0.05f));
  const std::vector<float> d = compute_scan_context(scan);
  const auto bytes = encode_scan_context(d);
  EXPECT_LT(bytes.size(), d.size() * sizeof(float) / 4);
  std::string error;
  const auto back = decode_scan_context(bytes, &error);
  ASSERT_TRUE(back) << error;
  ASSERT_EQ(back->size(), d.size());
  for (size_t i = 0; i < d.size(); ++i) EXPECT_NEAR((*back)[i], d[i], 1.0 / 64 + 1e-6);
  EXPECT_LT(scan_context_distance(d, *back).distance, 0.01);
  auto bad = bytes;
  bad.resize(bad.size() / 2);
  EXPECT_FALSE(decode_scan_context(bad, &error));
}

}  // namespace cairn
