// SendWindow: at most `limit` keyframes unacknowledged in DDS; the rest wait, in order.
#include "robot_agent/app/send_window.h"

#include <gtest/gtest.h>

#include <vector>

namespace cairn::agent {
namespace {

struct Sample {
  int32_t s;
  int32_t seq() const { return s; }
};

std::vector<int32_t> released(SendWindow<Sample>* w) {
  std::vector<int32_t> out;
  w->release([&](const Sample& x) { out.push_back(x.seq()); });
  return out;
}

TEST(SendWindow, AtMostLimitUnacknowledgedAndTheRestInOrderAsAcksCome) {
  SendWindow<Sample> w(3);
  for (int32_t i = 0; i < 8; ++i) w.push({i});
  EXPECT_EQ(released(&w), (std::vector<int32_t>{0, 1, 2}));
  EXPECT_TRUE(released(&w).empty()) << "nothing more before an acknowledgement";
  EXPECT_EQ(w.waiting(), 5u);
  w.acknowledged(0);
  EXPECT_EQ(released(&w), (std::vector<int32_t>{3}));
  w.acknowledged(-1);  // an older ack changes nothing
  EXPECT_TRUE(released(&w).empty());
  w.acknowledged(4);  // acks may cover more than was released (an earlier run's)
  EXPECT_EQ(released(&w), (std::vector<int32_t>{4, 5, 6, 7}));
  EXPECT_TRUE(w.empty());
}

TEST(SendWindow, WithoutALimitEverythingGoesAtOnce) {
  SendWindow<Sample> w(0);
  for (int32_t i = 0; i < 100; ++i) w.push({i});
  EXPECT_EQ(released(&w).size(), 100u);
  EXPECT_TRUE(w.empty());
}

}  // namespace
}  // namespace cairn::agent
