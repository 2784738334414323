#include "dds/conversions.h"

#include <gtest/gtest.h>

#include "cairn_msgsPubSubTypes.h"
#include "dds/cdr.h"

#include <cmath>
#include <cstring>
#include <limits>

namespace cairn::dds {
namespace {

Keyframe make_keyframe() {
  Keyframe kf;
  kf.id = {RobotId(2), 7};
  kf.stamp_ns = 123456789;
  kf.T_local_base = SE2(1.5, -2.0, 0.3);
  kf.T_prev_this = SE2(0.5, 0.01, 0.02);
  kf.scan.angle_min_rad = -M_PI;
  kf.scan.angle_increment_rad = float(2 * M_PI / 360);
  kf.scan.range_max_m = 12.f;
  for (int i = 0; i < 360; ++i) kf.scan.ranges_m.push_back(1.0f + 0.01f * i);
  kf.place_descriptor = {1.f, 2.f, 3.f, 0.5f};
  return kf;
}

TEST(Conversions, KeyframeRoundTripKeepsPoseAndScanToAMillimetre) {
  const Keyframe kf = make_keyframe();
  std::string error;
  auto back = from_msg(to_msg(kf), &error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(back->id, kf.id);
  EXPECT_EQ(back->stamp_ns, kf.stamp_ns);
  EXPECT_NEAR(back->T_local_base.x(), 1.5, 1e-12);
  EXPECT_NEAR(back->T_prev_this.yaw(), 0.02, 1e-12);
  ASSERT_EQ(back->scan.ranges_m.size(), 360u);
  for (size_t i = 0; i < 360; ++i) EXPECT_NEAR(back->scan.ranges_m[i], kf.scan.ranges_m[i], 5e-4);
  EXPECT_EQ(back->place_descriptor, kf.place_descriptor);
}

TEST(Conversions, KeyframeWithNanPoseIsRejectedNamingTheField) {
  auto msg = to_msg(make_keyframe());
  msg.T_local_base().x_m(std::nan(""));
  std::string error;
  EXPECT_FALSE(from_msg(msg, &error));
  EXPECT_NE(error.find("T_local_base"), std::string::npos) << error;
}

TEST(Conversions, KeyframeWithCorruptScanIsRejected) {
  auto msg = to_msg(make_keyframe());
  msg.scan_zstd().resize(msg.scan_zstd().size() / 2);
  std::string error;
  EXPECT_FALSE(from_msg(msg, &error));
  EXPECT_NE(error.find("scan_zstd"), std::string::npos) << error;
}

TEST(Conversions, KeyframeLandmarksRoundTripAndNanIsRejected) {
  Keyframe kf = make_keyframe();
  kf.landmarks.push_back(LandmarkObservation{LandmarkId(12), 123, 3.25, -0.5, 0.05, 0.02});
  kf.landmarks.push_back(LandmarkObservation{LandmarkId(3), 456, 1.0, 2.0, 0.1, 0.01});
  std::string error;
  auto back = from_msg(to_msg(kf), &error);
  ASSERT_TRUE(back) << error;
  ASSERT_EQ(back->landmarks.size(), 2u);
  EXPECT_EQ(back->landmarks[0].id, LandmarkId(12));
  EXPECT_EQ(back->landmarks[1].stamp_ns, 456);
  EXPECT_NEAR(back->landmarks[0].range_m, 3.25, 1e-6);
  EXPECT_NEAR(back->landmarks[0].bearing_rad, -0.5, 1e-6);
  EXPECT_NEAR(back->landmarks[1].sigma_bearing_rad, 0.01, 1e-6);
  auto msg = to_msg(kf);
  msg.landmarks()[1].bearing_rad(std::nanf(""));
  EXPECT_FALSE(from_msg(msg, &error));
  EXPECT_NE(error.find("landmarks[1]: bearing_rad must be finite"), std::string::npos) << error;
  msg = to_msg(kf);
  msg.landmarks()[0].landmark_id(-4);
  EXPECT_FALSE(from_msg(msg, &error));
  EXPECT_NE(error.find("landmarks[0]: invalid landmark id"), std::string::npos) << error;
}

TEST(Conversions, KeyframeSalientPointsRoundTripAndBadWeightsAreNamed) {
  Keyframe kf = make_keyframe();
  kf.salient.push_back(SalientPoint{2.5f, -1.0f, 0.75f});
  kf.salient.push_back(SalientPoint{4.0f, 0.5f, 1.0f});
  std::string error;
  auto back = from_msg(to_msg(kf), &error);
  ASSERT_TRUE(back) << error;
  ASSERT_EQ(back->salient.size(), 2u);
  EXPECT_FLOAT_EQ(back->salient[0].x_m, 2.5f);
  EXPECT_FLOAT_EQ(back->salient[0].y_m, -1.0f);
  EXPECT_FLOAT_EQ(back->salient[1].weight, 1.0f);
  for (const float bad : {std::nanf(""), -0.1f, 1.5f}) {
    auto msg = to_msg(kf);
    msg.salient()[1].weight(bad);
    EXPECT_FALSE(from_msg(msg, &error)) << bad;
    EXPECT_NE(error.find("salient[1]"), std::string::npos) << error;
  }
  auto msg = to_msg(kf);
  msg.salient()[0].x_m(std::numeric_limits<float>::infinity());
  EXPECT_FALSE(from_msg(msg, &error));
  EXPECT_NE(error.find("salient[0]"), std::string::npos) << error;
}

TEST(Conversions, KeyframePosesRoundTripAndBadSamplesAreNamed) {
  const KeyframePoses poses{RobotId(2), 7'000'000'000, {{0, SE2(0, 0, 0)}, {1, SE2(1.5, -0.25, 0.3)}}};
  std::string error;
  const auto back = from_msg(to_msg(poses), &error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(back->robot, RobotId(2));
  EXPECT_EQ(back->stamp_ns, poses.stamp_ns);
  ASSERT_EQ(back->poses.size(), 2u);
  EXPECT_EQ(back->poses[1].seq, 1);
  EXPECT_TRUE(back->poses[1].T_local_base.vector().isApprox(poses.poses[1].T_local_base.vector()));
  cairn_msgs::KeyframePoses nan = to_msg(poses);
  nan.T_local_base()[1].yaw_rad(std::nan(""));
  EXPECT_FALSE(from_msg(nan, &error));
  EXPECT_NE(error.find("non-finite T_local_base of seq 1"), std::string::npos) << error;
  cairn_msgs::KeyframePoses short_poses = to_msg(poses);
  short_poses.T_local_base().pop_back();
  EXPECT_FALSE(from_msg(short_poses, &error));
  EXPECT_NE(error.find("2 seqs but 1 poses"), std::string::npos) << error;
}

ObjectReport make_object(const std::string& class_name, int anchor_seq, int points) {
  ObjectReport o;
  o.id = {RobotId(1), 3};
  o.class_name = class_name;
  o.confidence = 0.8f;
  o.anchor_seq = anchor_seq;
  o.T_anchor_object.translation() = Eigen::Vector3d(1, 2, 0.3);
  for (int i = 0; i < points; ++i) o.cloud.push_back({0.01f * i, -0.01f * i, 0.2f, 200, 10, 10});
  return o;
}

TEST(Conversions, ObjectRoundTripAndBadConfidence) {
  const ObjectReport o = make_object("victim", 4, 100);
  std::string error;
  auto back = from_msg(to_msg(o), &error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(back->class_name, "victim");
  ASSERT_EQ(back->cloud.size(), 100u);
  EXPECT_NEAR(back->cloud[50].x, 0.5f, 1e-3);
  EXPECT_EQ(back->cloud[50].r, 200);
  EXPECT_NEAR(back->T_anchor_object.translation().y(), 2.0, 1e-12);

  auto msg = to_msg(o);
  msg.confidence(std::nanf(""));
  EXPECT_FALSE(from_msg(msg, &error));
  EXPECT_NE(error.find("confidence"), std::string::npos);
}

// The base station's journal stores samples as CDR bytes: they must come back whole, and cut or
// corrupt bytes must be refused, never half-read.
TEST(Conversions, CdrBytesComeBackWholeAndCutOnesAreRefused) {
  const ObjectReport o = make_object("hazard", 9, 50);
  const auto bytes = to_cdr<cairn_msgs::ObjectReportPubSubType>(to_msg(o));
  ASSERT_GT(bytes.size(), 50u);
  cairn_msgs::ObjectReport msg;
  ASSERT_TRUE((from_cdr<cairn_msgs::ObjectReportPubSubType>(bytes, &msg)));
  std::string error;
  const auto back = from_msg(msg, &error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(back->class_name, "hazard");
  EXPECT_EQ(back->anchor_seq, 9);
  EXPECT_EQ(back->cloud.size(), 50u);

  const auto kf_bytes = to_cdr<cairn_msgs::KeyframePubSubType>(to_msg(make_keyframe()));
  cairn_msgs::Keyframe kf;
  ASSERT_TRUE((from_cdr<cairn_msgs::KeyframePubSubType>(kf_bytes, &kf)));
  EXPECT_EQ(kf.seq(), 7);
  EXPECT_TRUE(from_msg(kf, &error)) << error;

  std::vector<uint8_t> cut(kf_bytes.begin(), kf_bytes.begin() + long(kf_bytes.size() / 2));
  EXPECT_FALSE((from_cdr<cairn_msgs::KeyframePubSubType>(cut, &kf)));
  // The scan's length field, after the encapsulation (4 bytes) and the fixed part (robot, seq,
  // stamp, two poses, two covariances), set to 4 GiB.
  const size_t length_at = 4 + 4 + 4 + 8 + 24 + 72 + 24 + 72;
  uint32_t length = 0;
  std::memcpy(&length, kf_bytes.data() + length_at, 4);
  ASSERT_EQ(length, kf.scan_zstd().size());
  std::vector<uint8_t> absurd = kf_bytes;
  for (size_t i = length_at; i < length_at + 4; ++i) absurd[i] = 0xff;
  EXPECT_FALSE((from_cdr<cairn_msgs::KeyframePubSubType>(absurd, &kf)));
  EXPECT_FALSE((from_cdr<cairn_msgs::KeyframePubSubType>({}, &kf)));
}

TEST(Conversions, RgbdFrameWithWrongSizesIsRejected) {
  RgbdFrame f;
  f.intrinsics = {4, 3, 100, 100, 2, 1.5, 0.001};
  f.rgb.assign(4 * 3 * 3, 0);
  f.depth.assign(4 * 3, 1000);
  std::string error;
  ASSERT_TRUE(from_msg(to_msg(RobotId(0), f), &error)) << error;
  auto msg = to_msg(RobotId(0), f);
  msg.depth().pop_back();
  EXPECT_FALSE(from_msg(msg, &error));
  EXPECT_NE(error.find("sizes"), std::string::npos);
  msg = to_msg(RobotId(0), f);
  msg.T_base_camera()[0] = 5.0;  // not a rotation
  EXPECT_FALSE(from_msg(msg, &error));
}

TEST(Conversions, LaserScanKeepsNanRangesButRejectsBadGeometry) {
  LaserScan s;
  s.angle_increment_rad = 0.01f;
  s.ranges_m = {1.f, std::nanf(""), INFINITY};
  std::string error;
  auto back = from_msg(to_msg(RobotId(0), s), &error);
  ASSERT_TRUE(back) << error;
  EXPECT_TRUE(std::isnan(back->ranges_m[1]));
  auto msg = to_msg(RobotId(0), s);
  msg.range_max_m(0.f);
  EXPECT_FALSE(from_msg(msg, &error));
  msg = to_msg(RobotId(-3), s);
  EXPECT_FALSE(from_msg(msg, &error));
  EXPECT_NE(error.find("robot_id"), std::string::npos);
  s.intensities = {0.3f, 0.3f, 1.0f};
  back = from_msg(to_msg(RobotId(0), s), &error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(back->intensities, s.intensities);
  msg = to_msg(RobotId(0), s);
  msg.intensities().pop_back();
  EXPECT_FALSE(from_msg(msg, &error));
  EXPECT_NE(error.find("2 intensities for 3 beams"), std::string::npos) << error;
}

TEST(Conversions, SamplesForAnotherRobotAreNamed) {
  std::string error;
  EXPECT_TRUE(check_robot(3, RobotId(3), &error));
  EXPECT_FALSE(check_robot(7, RobotId(3), &error));
  EXPECT_EQ(error, "sample for unknown robot_id 7 on robot3's topic");
}

}  // namespace
}  // namespace cairn::dds
