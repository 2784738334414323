#include "common/check.h"

#include <gtest/gtest.h>

namespace cairn {
namespace {

int at(const int* values, int size, int index) {
  CAIRN_CHECK(index >= 0 && index < size, "index " + std::to_string(index) + " out of 0.." + std::to_string(size));
  return values[index];
}

TEST(Check, PassesSilentlyWhenTheInvariantHolds) {
  const int values[] = {4, 5, 6};
  EXPECT_EQ(at(values, 3, 2), 6);
}

TEST(CheckDeathTest, AbortsNamingTheConditionTheFileAndTheMessage) {
  const int values[] = {4, 5, 6};
  EXPECT_DEATH(at(values, 3, 7),
               "check_test.cpp:[0-9]+: invariant broken: CAIRN_CHECK\\(index >= 0 && index < "
               "size\\): index 7 out of 0..3");
}

}  // namespace
}  // namespace cairn
