// Real Fast DDS in one process: a writer and a reader on a private domain exchange samples,
// including an RGB-D frame far above the default 512 KiB shared-memory segment.
#include "dds/endpoints.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <memory>
#include <set>
#include <thread>

#include "cairn_msgsPubSubTypes.h"
#include "dds/conversions.h"
#include "dds/domain_lease.h"

namespace cairn::dds {
namespace {

// A domain no other test or mission on this host holds while this process runs.
int test_domain() {
  static const std::unique_ptr<DomainLease> lease = DomainLease::claim({}, nullptr);
  return lease ? lease->domain_id() : 0;
}

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
  Writer<RgbdTopic> writer(*participant, RobotId(1));
  Reader<RgbdTopic> reader(*participant, RobotId(1));
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

// The link's round trip is measured on arrival stamps (base_station/core/round_trip.h): a sample
// taken long after it arrived must still say when it arrived, on the clock reception_clock_ns reads.
TEST(Endpoints, EachSampleSaysWhenItArrivedNotWhenItWasTaken) {
  std::string error;
  auto participant = Participant::create({test_domain(), "endpoints_arrival_test"}, &error);
  ASSERT_TRUE(participant) << error;
  Writer<AckTopic> writer(*participant);
  Reader<AckTopic> reader(*participant);
  ASSERT_TRUE(writer.ok() && reader.ok());
  ASSERT_TRUE(wait_matched(writer, reader, 10.0));
  const int64_t before_ns = reception_clock_ns();
  cairn_msgs::Ack ack;
  ack.robot_id(3);
  ASSERT_TRUE(writer.write(ack));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the app is busy; the sample waits
  std::vector<Reader<AckTopic>::FromWriter> got;
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (got.empty() && std::chrono::steady_clock::now() < end) got = reader.take_all_from_writers();
  const int64_t taken_ns = reception_clock_ns();
  ASSERT_EQ(got.size(), 1u);
  EXPECT_GE(got[0].received_ns, before_ns);
  EXPECT_LT(got[0].received_ns, taken_ns - 250'000'000) << "stamped when taken, not when it arrived";
}

TEST(Endpoints, ManyObjectInstancesFromManyRobotsAllArrive) {
  // Regression: Fast DDS's default of 10 instances per endpoint silently refused the 11th object.
  std::string error;
  auto participant = Participant::create({test_domain(), "objects_test"}, &error);
  ASSERT_TRUE(participant) << error;
  Reader<ObjectTopic> reader(*participant);
  std::vector<std::unique_ptr<Writer<ObjectTopic>>> writers;
  for (int r = 0; r < 4; ++r) writers.push_back(std::make_unique<Writer<ObjectTopic>>(*participant));
  for (auto& w : writers) ASSERT_TRUE(wait_matched(*w, reader, 10.0));
  ObjectReport o;
  o.class_name = "victim";
  o.confidence = 0.5f;
  o.anchor_seq = 0;
  constexpr int kPerRobot = 12;
  for (int r = 0; r < 4; ++r) {
    for (int i = 0; i < kPerRobot; ++i) {
      o.id = {RobotId(r), i};
      ASSERT_TRUE(writers[r]->write(to_msg(o))) << "robot " << r << " object " << i;
    }
  }
  std::set<std::pair<int, int>> got;
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (got.size() < 4u * kPerRobot && std::chrono::steady_clock::now() < end) {
    for (const auto& m : reader.take_all()) got.insert({m.robot_id(), m.object_seq()});
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_EQ(got.size(), 4u * kPerRobot);
}

}  // namespace
}  // namespace cairn::dds
