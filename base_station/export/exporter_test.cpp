#include "base_station/export/exporter.h"
#include "base_station/core/multi_robot_mapper.h"
#include "base_station/core/object_verdicts.h"

#include <gtest/gtest.h>
#include <octomap/OcTree.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "base_station/core/synthetic_world_test_util.h"
#include "base_station/core/unlinked_robot_test_util.h"
#include "common/g2o_io.h"

namespace cairn::base {
namespace {

namespace fs = std::filesystem;
using testing::left_path;
using testing::right_path;

MultiRobotMapper make_mapper() {
  MapperOptions options;
  options.detect_loops = false;  // exact figures below assume the hinted starts only
  MultiRobotMapper mapper(options);
  mapper.set_robot_start(RobotId(0), left_path()[0]);
  mapper.set_robot_start(RobotId(1), right_path()[0]);
  for (const Keyframe& kf : testing::make_keyframes(RobotId(0), left_path(), testing::room_walls()))
    mapper.add_keyframe(kf);
  for (const Keyframe& kf : testing::make_keyframes(RobotId(1), right_path(), testing::room_walls()))
    mapper.add_keyframe(kf);
  for (const Keyframe& kf : testing::make_keyframes(RobotId(2), right_path(), testing::room_walls()))
    mapper.add_keyframe(kf);
  mapper.add_object(testing::make_object({RobotId(0), 0}, "victim", {4.3, 3.5, 0.2}, 3, left_path()[3]));
  mapper.add_object(testing::make_object({RobotId(1), 0}, "victim", {4.1, 3.4, 0.2}, 4, right_path()[4]));
  mapper.add_object(testing::make_object({RobotId(1), 1}, "hazard", {8.0, 2.0, 0.1}, 1, right_path()[1]));
  mapper.optimize();
  return mapper;
}

std::string temp_dir(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / ("cairn_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(p);
  return p.string();
}

std::vector<std::string> lines_of(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

int count_prefix(const std::vector<std::string>& lines, const std::string& prefix) {
  return int(std::count_if(lines.begin(), lines.end(), [&](const auto& l) { return l.rfind(prefix, 0) == 0; }));
}

TEST(Exporter, WritesEveryFileAndTheyParseBack) {
  const MultiRobotMapper mapper = make_mapper();
  const std::string dir = temp_dir("export");
  const ExportSummary summary = export_all(mapper.merged(), dir);
  for (const ExportedFile& f : summary.files) EXPECT_TRUE(f.ok) << f.path << ": " << f.error;
  ASSERT_TRUE(summary.ok());
  // map.pgm + map.yaml
  std::ifstream pgm(dir + "/map.pgm", std::ios::binary);
  std::string magic;
  pgm >> magic;
  EXPECT_EQ(magic, "P5");
  const YAML::Node yaml = YAML::LoadFile(dir + "/map.yaml");
  EXPECT_NEAR(yaml["resolution"].as<double>(), 0.05, 1e-9);
  // map.png
  std::ifstream png(dir + "/map.png", std::ios::binary);
  char sig[8] = {};
  png.read(sig, 8);
  EXPECT_EQ(std::string(sig + 1, 3), "PNG");
  // objects: 2 merged (victim from both robots, hazard)
  std::ifstream geojson_in(dir + "/objects.geojson");
  const nlohmann::json geojson = nlohmann::json::parse(geojson_in);
  EXPECT_EQ(geojson["type"], "FeatureCollection");
  ASSERT_EQ(geojson["features"].size(), 2u);
  EXPECT_EQ(geojson["features"][0]["properties"]["class"], "victim");
  EXPECT_EQ(geojson["features"][0]["properties"]["robots"].size(), 2u);
  EXPECT_EQ(lines_of(dir + "/objects.csv").size(), 3u);
  // PLY per object
  for (const GlobalObject& o : mapper.objects()) {
    pcl::PointCloud<pcl::PointXYZRGB> cloud;
    ASSERT_EQ(pcl::io::loadPLYFile(dir + "/object_" + object_key(o.id) + ".ply", cloud), 0);
    EXPECT_EQ(cloud.size(), o.cloud_global.size());
    EXPECT_NEAR(cloud[0].z, o.cloud_global[0].z, 1e-5);
  }
  // OctoMap
  octomap::OcTree tree(0.1);
  ASSERT_TRUE(tree.readBinary(dir + "/objects.bt"));
  EXPECT_GT(tree.size(), 0u);
  EXPECT_NEAR(tree.getResolution(), 0.03, 1e-9);
  octomap::OcTreeNode* node = tree.search(8.0, 2.0, 0.25);
  ASSERT_NE(node, nullptr);
  EXPECT_TRUE(tree.isNodeOccupied(node));
  // g2o: 12 linked keyframes, 10 odometry edges, 2 priors (robot 2 is not linked)
  const std::vector<std::string> g2o = lines_of(dir + "/graph.g2o");
  EXPECT_EQ(count_prefix(g2o, "VERTEX_SE2 "), 12);
  EXPECT_EQ(count_prefix(g2o, "EDGE_SE2 "), 10);
  EXPECT_EQ(count_prefix(g2o, "EDGE_PRIOR_SE2 "), 2);
  EXPECT_EQ(count_prefix(g2o, "# KEYFRAME "), 12);
  // the victim seen by both robots: one object node observed from both anchors
  EXPECT_EQ(count_prefix(g2o, "VERTEX_XY "), 1);
  EXPECT_EQ(count_prefix(g2o, "# OBJECT 12 0 0"), 1);
  EXPECT_EQ(count_prefix(g2o, "EDGE_SE2_XY "), 2);
  const G2oGraph read = read_g2o(dir + "/graph.g2o");
  EXPECT_EQ(read.vertices.size(), 12u);
  EXPECT_EQ(read.points.size(), 1u);
  // trajectories of linked robots only
  EXPECT_EQ(read_trajectory_csv(dir + "/trajectory_robot0.csv").size(), 6u);
  EXPECT_EQ(read_trajectory_csv(dir + "/trajectory_robot1.csv").size(), 6u);
  EXPECT_FALSE(fs::exists(dir + "/trajectory_robot2.csv"));
  fs::remove_all(dir);
}

TEST(Exporter, G2oLandmarksAreCartesianPointsWithPropagatedInformation) {
  KeyframePoseGraph graph;
  const KeyframeId k0{RobotId(0), 0}, k1{RobotId(0), 1};
  ASSERT_TRUE(graph.add_node(k0, SE2()));
  ASSERT_TRUE(graph.add_node(k1, SE2(1, 0, M_PI / 2)));
  graph.set_prior(PosePrior{k0, SE2()});
  ASSERT_TRUE(graph.add_edge(PoseGraphEdge{k0, k1, SE2(1, 0, M_PI / 2)}));
  // Marker 7 at (3, 0) and object robot1/obj4 at (1, 2): seen from k0 ahead, from k1 to its left.
  const double sr = 0.05, sb = 0.02;
  ASSERT_TRUE(graph.add_landmark_edge(LandmarkEdge{k0, LandmarkId(7), 3.0, 0.0, sr, sb}));
  ASSERT_TRUE(graph.add_landmark_edge(LandmarkEdge{k1, ObjectId{RobotId(1), 4}, 2.0, M_PI / 2, sr, sb}));
  ASSERT_TRUE(graph.add_landmark_edge(LandmarkEdge{k1, ObjectId{RobotId(1), 4}, 2.0, 0.0, sr, sb}));
  graph.solve();
  const std::string dir = temp_dir("g2o_landmarks");
  fs::create_directories(dir);
  std::string error;
  ASSERT_TRUE(write_graph_g2o(graph, dir + "/graph.g2o", &error)) << error;
  const std::vector<std::string> lines = lines_of(dir + "/graph.g2o");
  EXPECT_EQ(count_prefix(lines, "# MARKER 2 7"), 1);
  EXPECT_EQ(count_prefix(lines, "# OBJECT 3 1 4"), 1);
  const G2oGraph g = read_g2o(dir + "/graph.g2o");
  ASSERT_EQ(g.points.size(), 2u);
  ASSERT_EQ(g.point_edges.size(), 3u);
  const G2oPointEdge& marker = g.point_edges[0];
  EXPECT_EQ(marker.from, (G2oKey{0, 0}));
  EXPECT_EQ(marker.to, (G2oKey{0, 2}));
  EXPECT_NEAR(marker.p_from_to.x(), 3.0, 1e-9);
  EXPECT_NEAR(marker.p_from_to.y(), 0.0, 1e-9);
  // Bearing 0: radial = x, tangential = y with sigma range * sigma_bearing.
  EXPECT_NEAR(marker.information(0, 0), 1.0 / (sr * sr), 1e-6);
  EXPECT_NEAR(marker.information(1, 1), 1.0 / (3.0 * sb * 3.0 * sb), 1e-6);
  EXPECT_NEAR(marker.information(0, 1), 0.0, 1e-6);
  const G2oPointEdge& object = g.point_edges[1];
  EXPECT_EQ(object.from, (G2oKey{0, 1}));
  EXPECT_EQ(object.to, (G2oKey{0, 3}));
  EXPECT_NEAR(object.p_from_to.x(), 0.0, 1e-9);
  EXPECT_NEAR(object.p_from_to.y(), 2.0, 1e-9);
  // Bearing 90 deg: radial = y, tangential = x.
  EXPECT_NEAR(object.information(0, 0), 1.0 / (2.0 * sb * 2.0 * sb), 1e-6);
  EXPECT_NEAR(object.information(1, 1), 1.0 / (sr * sr), 1e-6);
  EXPECT_NEAR(g.points.at({0, 2}).x(), 3.0, 1e-6);
  // The object's two observations (2 m left of k1, 2 m ahead of k1) disagree: the solved point sits
  // between them and the exported residuals are what the graph had.
  EXPECT_GT(g2o_point_chi2(g, g.vertices, g.points), 1.0);
  fs::remove_all(dir);
}

TEST(Exporter, AnUnlinkedRobotsVictimIsInEveryExportFlaggedInItsOwnFrame) {
  const testing::UnlinkableRobot u;
  const std::string dir =
      (std::filesystem::temp_directory_path() / ("cairn_unplaced_" + std::to_string(::getpid()))).string();
  ASSERT_TRUE(export_all(u.mapper.merged(), dir).ok());
  std::ifstream csv(dir + "/objects.csv");
  std::string header, row;
  std::getline(csv, header);
  std::getline(csv, row);
  EXPECT_NE(header.find(",frame,aliases,local_robot,local_x_m,local_y_m"), std::string::npos) << header;
  EXPECT_EQ(row.rfind("1-0,victim,", 0), 0u) << row;
  EXPECT_NE(row.find(",robot1,"), std::string::npos) << row;
  std::ifstream geo_in(dir + "/objects.geojson");
  const nlohmann::json geo = nlohmann::json::parse(geo_in);
  ASSERT_EQ(geo["features"].size(), 1u);
  const auto& f = geo["features"][0];
  EXPECT_TRUE(f["geometry"].is_null()) << "not located on the global map";
  EXPECT_EQ(f["properties"]["frame"], "robot1");
  EXPECT_NEAR(f["properties"]["robot_frame_m"][0].get<double>(), 4.0, 0.05);
  EXPECT_NE(f["properties"]["where"].get<std::string>().find("robot 1 entered"), std::string::npos);
  EXPECT_TRUE(std::filesystem::file_size(dir + "/robot1_own_frame.png") > 100);
  std::filesystem::remove_all(dir);
}

TEST(Exporter, TheOperatorsVerdictIsInEveryObjectExport) {
  const MultiRobotMapper mapper = make_mapper();  // the merged map points into it
  MergedMap merged = mapper.merged();
  ASSERT_FALSE(merged.objects.empty());
  ObjectVerdicts verdicts;
  verdicts.set({merged.objects[0].id, ObjectVerdict::kConfirmed, "alive, trapped, needs a stretcher", sec_to_ns(5)});
  verdicts.apply(&merged.objects);
  const std::string dir = temp_dir("verdicts");
  fs::create_directories(dir);
  std::string error;
  ASSERT_TRUE(write_objects_csv(merged, dir + "/objects.csv", &error)) << error;
  ASSERT_TRUE(write_objects_geojson(merged, dir + "/objects.geojson", &error)) << error;
  std::ifstream csv(dir + "/objects.csv");
  std::string header, first, second;
  std::getline(csv, header);
  std::getline(csv, first);
  std::getline(csv, second);
  EXPECT_NE(header.find(",verdict,verdict_note"), std::string::npos) << header;
  EXPECT_NE(first.find(",confirmed,alive; trapped; needs a stretcher"), std::string::npos) << first;
  EXPECT_NE(second.find(",unreviewed,"), std::string::npos) << second;
  std::ifstream geo_in(dir + "/objects.geojson");
  const nlohmann::json geo = nlohmann::json::parse(geo_in);
  EXPECT_EQ(geo["features"][0]["properties"]["verdict"], "confirmed");
  EXPECT_EQ(geo["features"][0]["properties"]["verdict_note"], "alive, trapped, needs a stretcher");
  std::filesystem::remove_all(dir);
}

TEST(Exporter, UnwritableDirectoryIsReportedNotFatal) {
  const std::string file = temp_dir("not_a_dir");
  std::ofstream(file) << "x";
  const ExportSummary summary = export_all(make_mapper().merged(), file + "/sub");
  EXPECT_FALSE(summary.ok());
  ASSERT_GE(summary.failures(), 1);
  EXPECT_NE(summary.files[0].path.find(file), std::string::npos);
  EXPECT_FALSE(summary.files[0].error.empty());
  // Writing into an existing file path as a directory fails per file too.
  std::string error;
  EXPECT_FALSE(write_objects_csv(MultiRobotMapper().merged(), file + "/objects.csv", &error));
  EXPECT_FALSE(error.empty());
  fs::remove_all(file);
}

TEST(Exporter, RenderMapPngHasSignature) {
  const std::vector<uint8_t> png = render_map_png(make_mapper().merged());
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png[0], 0x89);
  EXPECT_EQ(png[1], 'P');
  const std::vector<uint8_t> empty = render_map_png(MultiRobotMapper().merged());
  ASSERT_GT(empty.size(), 8u);
}

uint32_t png_u32(const std::vector<uint8_t>& png, size_t at) {
  return uint32_t(png[at]) << 24 | uint32_t(png[at + 1]) << 16 | uint32_t(png[at + 2]) << 8 | png[at + 3];
}

TEST(Exporter, MapImageGeometryNamesThePointUnderEachPixel) {
  const MultiRobotMapper mapper = make_mapper();  // the merged map points into it
  const MergedMap merged = mapper.merged();
  const MapImageGeometry g = map_image_geometry(*merged.grid);
  ASSERT_TRUE(g.valid);
  const std::vector<uint8_t> png = render_map_png(merged);
  ASSERT_GT(png.size(), 24u);
  EXPECT_EQ(png_u32(png, 16), uint32_t(g.width_px));  // IHDR: width, height
  EXPECT_EQ(png_u32(png, 20), uint32_t(g.height_px));
  // An occupied wall cell: the pixel the formula gives for its centre lies in that very cell.
  const OccupancyGrid& grid = *merged.grid;
  int col = -1, row = -1;
  for (int r = 0; r < grid.height() && col < 0; ++r)
    for (int c = 0; c < grid.width() && col < 0; ++c)
      if (grid.known(c, r) && grid.probability(c, r) > 0.65) col = c, row = r;
  ASSERT_GE(col, 0);
  const Eigen::Vector2d centre = grid.cell_center_m(col, row);
  const double u = (centre.x() - g.x0_m) / g.m_per_px, v = (g.y_top_m - centre.y()) / g.m_per_px;
  EXPECT_GT(u, 0);
  EXPECT_LT(u, g.width_px);
  EXPECT_GT(v, 0);
  EXPECT_LT(v, g.height_px);
  const Eigen::Vector2d back(g.x0_m + u * g.m_per_px, g.y_top_m - v * g.m_per_px);
  EXPECT_EQ(grid.cell_of(back), Eigen::Vector2i(col, row));
  EXPECT_FALSE(map_image_geometry(*MultiRobotMapper().merged().grid).valid);
}

}  // namespace
}  // namespace cairn::base
