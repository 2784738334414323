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
  for (int r = 0; r < 6; ++r)
    for (int c = r; c < 6; ++c) info += r == c ? " 10" : " 0";
  const G2oGraph g = read_g2o(write_temp("q.g2o", "VERTEX_SE3:QUAT " + std::to_string(a0) + " 0 0 0 0 0 0 1\n" +
                                                      "EDGE_SE3:QUAT " + std::to_string(a0) + " " + std::to_string(b3) +
                                                      " 1 2 0 0 0 0.7071068 0.7071068" + info + "\n"));
  ASSERT_EQ(g.edges.size(), 1u);
  EXPECT_TRUE(g.robot_keys);
  EXPECT_NEAR(g.edges[0].T_from_to.yaw(), M_PI / 2, 1e-6);
  EXPECT_EQ(g.edges[0].to.robot, 1);
}

TEST(G2oIo, ReadsLandmarkPointsAndEdges) {
  // Pose 1 at (1, 0, 90 deg) sees point 2 (world (1, 2)) at (2, 0) in its frame.
  const std::string path = write_temp("xy.g2o",
                                      "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 1.5707963267948966\n"
                                      "# MARKER 2 7\nVERTEX_XY 2 1 2\n"
                                      "EDGE_SE2 0 1 1 0 1.5707963267948966 100 0 0 100 0 400\n"
                                      "EDGE_SE2_XY 1 2 2 0 25 1 50\nEDGE_SE2_XY 0 2 1 2 4 0 4\n");
  const G2oGraph g = read_g2o(path);
  ASSERT_EQ(g.vertices.size(), 2u);
  ASSERT_EQ(g.points.size(), 1u);
  ASSERT_EQ(g.point_edges.size(), 2u);
  EXPECT_EQ(g.edges.size(), 1u);
  const G2oPointEdge& e = g.point_edges[0];
  EXPECT_EQ(e.from, (G2oKey{0, 1}));
  EXPECT_EQ(e.to, (G2oKey{0, 2}));
  EXPECT_EQ(e.line, 6);
  EXPECT_DOUBLE_EQ(e.information(0, 1), 1.0);
  EXPECT_DOUBLE_EQ(e.information(1, 0), 1.0);
  EXPECT_DOUBLE_EQ(e.information(1, 1), 50.0);
  EXPECT_NEAR(g2o_point_chi2(g, g.vertices, g.points), 0.0, 1e-12);
  std::map<G2oKey, Eigen::Vector2d> moved = g.points;
  moved[{0, 2}].x() += 0.1;  // in pose 1's frame that is -0.1 along its y: 50 * 0.01 = 0.5; pose 0: 4 * 0.01
  EXPECT_NEAR(g2o_point_chi2(g, g.vertices, moved), 0.5 + 0.04, 1e-9);
  // The points do not join the pose graph (odometry initialisation, chi2) and round-trip.
  EXPECT_EQ(initialize_from_odometry(g).size(), 2u);
  const std::string out = ::testing::TempDir() + "xy_out.g2o";
  ASSERT_TRUE(write_g2o(out, g));
  const G2oGraph back = read_g2o(out);
  ASSERT_EQ(back.point_edges.size(), 2u);
  EXPECT_EQ(back.points.at({0, 2}), Eigen::Vector2d(1, 2));
  EXPECT_EQ(back.point_edges[0].information, e.information);
  G2oGraph merged = g;
  merge_g2o(back, &merged);
  EXPECT_EQ(merged.point_edges.size(), 2u) << "the same edges from another file are duplicates";
}

TEST(G2oIo, MalformedLandmarkLinesNameTheLine) {
  auto expect_error = [](const std::string& name, const std::string& text, const std::string& what) {
    try {
      read_g2o(write_temp(name, text));
      ADD_FAILURE() << name << ": expected InputError";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  const std::string poses = "VERTEX_SE2 0 0 0 0\n";
  expect_error("xy_nan.g2o", poses + "VERTEX_XY 1 nan 2\n", "xy_nan.g2o:2: VERTEX_XY: non-finite");
  expect_error("xy_short.g2o", poses + "VERTEX_XY 1 2\n", "xy_short.g2o:2: VERTEX_XY expects 2 numbers");
  expect_error("xy_extra.g2o", poses + "VERTEX_XY 1 2 3 4\n", "xy_extra.g2o:2: VERTEX_XY: unexpected extra");
  expect_error("exy_nan.g2o", poses + "VERTEX_XY 1 2 3\nEDGE_SE2_XY 0 1 1 inf 1 0 1\n",
               "exy_nan.g2o:3: EDGE_SE2_XY: non-finite");
  expect_error("exy_short.g2o", poses + "VERTEX_XY 1 2 3\nEDGE_SE2_XY 0 1 1 1 1 0\n",
               "exy_short.g2o:3: EDGE_SE2_XY expects 3 numbers");
  expect_error("exy_npd.g2o", poses + "VERTEX_XY 1 2 3\nEDGE_SE2_XY 0 1 1 1 1 2 1\n",
               "exy_npd.g2o:3: EDGE_SE2_XY: information not positive definite");
  expect_error("exy_id.g2o", poses + "EDGE_SE2_XY 0 x 1 1 1 0 1\n", "exy_id.g2o:2: EDGE_SE2_XY: bad vertex id");
  expect_error("xy_both.g2o", poses + "VERTEX_XY 0 1 1\n", "xy_both.g2o:2: VERTEX_XY: id 0 is already a VERTEX_SE2");
  expect_error("se2_both.g2o", "VERTEX_XY 0 1 1\n" + poses, "se2_both.g2o:2: VERTEX_SE2: id 0 is already a VERTEX_XY");
  expect_error("exy_kinds.g2o", poses + "VERTEX_SE2 1 0 0 0\nEDGE_SE2_XY 0 1 1 1 1 0 1\n",
               "exy_kinds.g2o:3: EDGE_SE2_XY: second vertex is a VERTEX_SE2");
  expect_error("exy_from.g2o", poses + "VERTEX_XY 1 2 3\nVERTEX_XY 2 2 3\nEDGE_SE2_XY 1 2 1 1 1 0 1\n",
               "exy_from.g2o:4: EDGE_SE2_XY: first vertex is a VERTEX_XY");
  expect_error("se2_point.g2o", poses + "VERTEX_XY 1 2 3\nEDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n",
               "se2_point.g2o:3: EDGE_SE2/SE3 joins a VERTEX_XY");
}

}  // namespace
}  // namespace cairn
