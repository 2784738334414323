#include "common/g2o_io.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include "common/errors.h"

namespace cairn {
namespace {

std::string write_temp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

TEST(G2oIo, ReadsSe2AndRoundTrips) {
  const std::string path = write_temp("a.g2o",
                                      "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0.1\n"
                                      "EDGE_SE2 0 1 1 0 0.1 100 0 0 100 0 400\n");
  const G2oGraph g = read_g2o(path);
  ASSERT_EQ(g.vertices.size(), 2u);
  ASSERT_EQ(g.edges.size(), 1u);
  EXPECT_DOUBLE_EQ(g.edges[0].information(2, 2), 400);
  EXPECT_NEAR(g2o_chi2(g, g.vertices), 0.0, 1e-12);
  EXPECT_NEAR(sesync_objective(g, g.vertices), 0.0, 1e-12);
  const std::string out = ::testing::TempDir() + "b.g2o";
  ASSERT_TRUE(write_g2o(out, g));
  const G2oGraph back = read_g2o(out);
  EXPECT_EQ(back.edges.size(), 1u);
  EXPECT_NEAR(back.vertices.at({0, 1}).yaw(), 0.1, 1e-9);
}

TEST(G2oIo, MalformedLineNamesFileAndLine) {
  const std::string path = write_temp("bad.g2o", "VERTEX_SE2 0 0 0 0\nEDGE_SE2 0 1 1 0 zero 1 0 0 1 0 1\n");
  try {
    read_g2o(path);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.g2o:2"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_g2o(write_temp("nan.g2o", "EDGE_SE2 0 1 nan 0 0 1 0 0 1 0 1\n")), InputError);
  EXPECT_THROW(read_g2o(write_temp("short.g2o", "EDGE_SE2 0 1 1 0 0 1 0 0\n")), InputError);
  EXPECT_THROW(read_g2o(write_temp("npd.g2o", "EDGE_SE2 0 1 1 0 0 -1 0 0 1 0 1\n")), InputError);
}

TEST(G2oIo, EdgesOnlyInitialisedFromOdometry) {
  const G2oGraph g = read_g2o(write_temp("e.g2o",
                                         "EDGE_SE2 0 1 1 0 1.5707963 1 0 0 1 0 1\n"
                                         "EDGE_SE2 1 2 1 0 0 1 0 0 1 0 1\n"
                                         "EDGE_SE2 0 2 5 5 0 1 0 0 1 0 1\n"));
  const auto poses = initialize_from_odometry(g);
  ASSERT_EQ(poses.size(), 3u);
  EXPECT_NEAR(poses.at({0, 2}).x(), 1.0, 1e-6);
  EXPECT_NEAR(poses.at({0, 2}).y(), 1.0, 1e-6);
}

TEST(G2oIo, MultiRobotKeysAndSe3Quat) {
  const uint64_t a0 = (uint64_t('a') << 56), b3 = (uint64_t('b') << 56) | 3;
  EXPECT_EQ(decode_g2o_key(b3).robot, 1);
  EXPECT_EQ(decode_g2o_key(b3).index, 3);
  EXPECT_EQ(encode_g2o_key({1, 3}), b3);
  std::string info;
  for (int r = 0; r < 6; ++r) for (int c = r; c < 6; ++c) info += r == c ? " 10" : " 0";
  const G2oGraph g = read_g2o(write_temp("q.g2o", "VERTEX_SE3:QUAT " + std::to_string(a0) + " 0 0 0 0 0 0 1\n" +
                                                      "EDGE_SE3:QUAT " + std::to_string(a0) + " " + std::to_string(b3) +
                                                      " 1 2 0 0 0 0.7071068 0.7071068" + info + "\n"));
  ASSERT_EQ(g.edges.size(), 1u);
  EXPECT_TRUE(g.robot_keys);
  EXPECT_NEAR(g.edges[0].T_from_to.yaw(), M_PI / 2, 1e-6);
  EXPECT_EQ(g.edges[0].to.robot, 1);
}

}  // namespace
}  // namespace cairn
