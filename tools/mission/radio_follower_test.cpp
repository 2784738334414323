#include "tools/mission/radio_follower.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <sstream>

namespace cairn::mission {
namespace {

TEST(RadioSummary, CountsEachRobotsCutsAndTheTimeItWasOutOfRange) {
  std::istringstream csv(
      "t_s,robot,received_dbm,walls,up\n"
      "0,0,-40,0,1\n0,1,-50,1,1\n"
      "0.5,0,-41,0,1\n0.5,1,-85,4,0\n"
      "1,0,-42,0,1\n1,1,-90,5,0\n"
      "1.5,0,-42,0,1\n1.5,1,-70,2,1\n"
      "garbage\n"
      "2,0,-42,0,1\n2,1,-86,4,0\n"
      "2.5,0,-42,0,1\n2.5,1,-86,4,0\n");
  int malformed = 0;
  const auto s = summarize_radio(csv, &malformed);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(malformed, 1);
  EXPECT_EQ(s[0].robot, 0);
  EXPECT_EQ(s[0].cuts, 0);
  EXPECT_DOUBLE_EQ(s[0].out_of_range_s, 0.0);
  EXPECT_DOUBLE_EQ(s[0].first_cut_s, -1.0);
  EXPECT_EQ(s[1].cuts, 2);
  EXPECT_DOUBLE_EQ(s[1].out_of_range_s, 1.5);  // 0.5 -> 1.5 and 2 -> 2.5
  EXPECT_DOUBLE_EQ(s[1].lowest_dbm, -90.0);
  EXPECT_DOUBLE_EQ(s[1].first_cut_s, 0.5);
}

TEST(RadioFollower, AppliesEachChangeOnceAsTheSimulatorWritesIt) {
  char path[] = "/tmp/cairn_radio_test_XXXXXX";
  const int fd = mkstemp(path);
  ASSERT_GE(fd, 0);
  close(fd);
  std::vector<std::pair<int, bool>> applied;
  bool refuse = false;
  RadioFollower follower(path, [&](int robot, bool cut, std::string* error) {
    if (refuse) {
      *error = "no such robot";
      return false;
    }
    applied.push_back({robot, cut});
    return true;
  });
  std::ofstream out(path, std::ios::app);
  out << "t_s,robot,received_dbm,walls,up\n0,0,-40,0,1\n0,1,-50,1,1\n" << std::flush;
  EXPECT_TRUE(follower.poll().empty());            // up from the start: nothing to do
  out << "0.5,1,-85,4,0\n0.5,0,-4" << std::flush;  // the second line is still being written
  const auto cut = follower.poll();
  ASSERT_EQ(cut.size(), 1u);
  EXPECT_NE(cut[0].find("radio: robot 1 out of range at mission t=0.5 s (-85 dBm, 4 walls)"), std::string::npos)
      << cut[0];
  out << "1,0,1\n1,1,-86,4,0\n" << std::flush;  // robot 0's line completed; robot 1 still cut
  EXPECT_TRUE(follower.poll().empty());
  refuse = true;
  out << "1.5,1,-70,2,1\n" << std::flush;
  const auto failed = follower.poll();
  ASSERT_EQ(failed.size(), 1u);
  EXPECT_NE(failed[0].find("NOT APPLIED: no such robot"), std::string::npos) << failed[0];
  refuse = false;
  out << "2,1,-70,2,1\n" << std::flush;  // tried again with the next reading
  EXPECT_EQ(follower.poll().size(), 1u);
  const std::vector<std::pair<int, bool>> expected{{1, true}, {1, false}};
  EXPECT_EQ(applied, expected);
  std::remove(path);
}

}  // namespace
}  // namespace cairn::mission
