// Real Fast DDS in one process: a writer and a reader on a private domain exchange samples,
// including an RGB-D frame far above the default 512 KiB shared-memory segment.
#include "dds/endpoints.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "cairn_msgsPubSubTypes.h"
#include "dds/conversions.h"

namespace cairn::dds {
namespace {

int test_domain() { return 100 + int(getpid() % 100); }

template <typename W, typename R>
bool wait_matched(W& w, R& r, double timeout_s) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < end) {
    if (w.matched_readers() > 0 && r.matched_writers() > 0) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

TEST(Endpoints, LargeRgbdFramesArriveIntactAndInOrder) {
  std::string error;
  auto participant = Participant::create({test_domain(), "endpoints_test"}, &error);
  ASSERT_TRUE(participant) << error;
  Writer<cairn_msgs::RgbdFrame, cairn_msgs::RgbdFramePubSubType> writer(*participant, kRgbdTopic, TopicKind::kSensor);
  Reader<cairn_msgs::RgbdFrame, cairn_msgs::RgbdFramePubSubType> reader(*participant, kRgbdTopic, TopicKind::kSensor);
  ASSERT_TRUE(writer.ok() && reader.ok());
  ASSERT_TRUE(wait_matched(writer, reader, 10.0));

  RgbdFrame f;
  f.intrinsics = {640, 480, 525, 525, 319.5, 239.5, 0.001};
  f.rgb.resize(640 * 480 * 3);
  f.depth.resize(640 * 480);
  for (size_t i = 0; i < f.depth.size(); ++i) f.depth[i] = uint16_t(i % 5000);
  constexpr int kFrames = 5;
  for (int i = 0; i < kFrames; ++i) {
    f.stamp_ns = i;
    ASSERT_TRUE(writer.write(to_msg(RobotId(1), f)));
  }
  EXPECT_GT(writer.bytes_written(), uint64_t(kFrames) * 900'000);
  std::vector<cairn_msgs::RgbdFrame> got;
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (got.size() < kFrames && std::chrono::steady_clock::now() < end) {
    for (auto& m : reader.take_all()) got.push_back(std::move(m));
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_EQ(got.size(), size_t(kFrames));
  for (int i = 0; i < kFrames; ++i) {
    auto back = from_msg(got[i], &error);
    ASSERT_TRUE(back) << error;
    EXPECT_EQ(back->stamp_ns, i);
    EXPECT_EQ(back->depth[12345], f.depth[12345]);
  }
}

}  // namespace
}  // namespace cairn::dds
