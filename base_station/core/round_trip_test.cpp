#include "base_station/core/round_trip.h"

#include <gtest/gtest.h>

namespace cairn::base {
namespace {

constexpr uint64_t kMs = 1000000;

TEST(RoundTrip, TheRobotsHoldingTimeIsTakenOffAndTheMedianShrugsOffOneSlowEcho) {
  RoundTrip rt;
  EXPECT_FALSE(rt.median_ms());
  // Probe at 1000 ms, the robot held it 300 ms, its status arrived at 1340 ms: 40 ms on the radio.
  ASSERT_TRUE(rt.add(1000 * kMs, 300 * kMs, 1340 * kMs));
  EXPECT_DOUBLE_EQ(*rt.median_ms(), 40.0);
  ASSERT_TRUE(rt.add(2000 * kMs, 100 * kMs, 2150 * kMs));  // 50 ms
  ASSERT_TRUE(rt.add(3000 * kMs, 0, 5000 * kMs));          // one retransmission: 2 s
  EXPECT_DOUBLE_EQ(*rt.median_ms(), 50.0);
  // The same probe echoed again (no ack came since): a later status, a longer hold, the same trip.
  EXPECT_FALSE(rt.add(3000 * kMs, 900 * kMs, 5900 * kMs));
  EXPECT_DOUBLE_EQ(*rt.median_ms(), 50.0);
}

TEST(RoundTrip, EchoesThatDoNotAddUpAreRefused) {
  RoundTrip rt;
  EXPECT_FALSE(rt.add(0, 0, 10 * kMs)) << "no ack taken yet";
  EXPECT_FALSE(rt.add(20 * kMs, 0, 10 * kMs)) << "a probe from the base's future";
  EXPECT_FALSE(rt.add(10 * kMs, 30 * kMs, 20 * kMs)) << "held longer than it was away";
  EXPECT_FALSE(rt.median_ms());
}

TEST(RoundTrip, OnlyTheNewestWindowCounts) {
  RoundTripOptions o;
  o.window = 3;
  RoundTrip rt(o);
  for (uint64_t i = 1; i <= 3; ++i) rt.add(i * 1000 * kMs, 0, i * 1000 * kMs + 500 * kMs);  // 500 ms each
  for (uint64_t i = 4; i <= 5; ++i) rt.add(i * 1000 * kMs, 0, i * 1000 * kMs + 20 * kMs);   // then 20 ms
  EXPECT_DOUBLE_EQ(*rt.median_ms(), 20.0);
}

}  // namespace
}  // namespace cairn::base
