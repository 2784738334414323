// RGB-ICP (Algorithm 3) on real data from ../shared/data (tests skip loudly when it is absent).
#include "common/registration/rgb_icp.h"

#include <gtest/gtest.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "robot_agent/core/objects/cloud_filter.h"

namespace cairn::agent {
namespace {

using registration::rgb_icp;
using registration::RgbIcpOptions;
using registration::RgbIcpResult;

const std::string kData = CAIRN_SHARED_DATA_DIR;

double rotation_deg(const Eigen::Isometry3d& T) { return Eigen::AngleAxisd(T.linear()).angle() * 180.0 / M_PI; }

// Coloured cloud of an Open3D RGB-D frame (PrimeSense intrinsics, depth in mm), every 2nd pixel.
ColoredCloud open3d_frame(int i) {
  char name[16];
  std::snprintf(name, sizeof name, "%05d", i);
  const std::string dir = kData + "/rgbd/open3d_testdata/RGBD/";
  const cv::Mat bgr = cv::imread(dir + "color/" + name + ".jpg", cv::IMREAD_COLOR);
  const cv::Mat depth = cv::imread(dir + "depth/" + name + ".png", cv::IMREAD_ANYDEPTH);
  ColoredCloud cloud;
  if (bgr.empty() || depth.empty()) return cloud;
  for (int v = 0; v < depth.rows; v += 2)
    for (int u = 0; u < depth.cols; u += 2) {
      const double z = depth.at<uint16_t>(v, u) * 0.001;
      if (z <= 0.1 || z > 3.0) continue;
      const cv::Vec3b c = bgr.at<cv::Vec3b>(v, u);
      cloud.push_back(
          ColoredPoint{float((u - 319.5) * z / 525.0), float((v - 239.5) * z / 525.0), float(z), c[2], c[1], c[0]});
    }
  return cloud;
}

std::vector<Eigen::Isometry3d> open3d_trajectory() {
  std::ifstream in(kData + "/rgbd/open3d_testdata/RGBD/trajectory.log");
  std::vector<Eigen::Isometry3d> poses;
  int a, b, c;
  while (in >> a >> b >> c) {
    Eigen::Matrix4d m;
    for (int r = 0; r < 4; ++r)
      for (int k = 0; k < 4; ++k) in >> m(r, k);
    Eigen::Isometry3d T;
    T.matrix() = m;
    poses.push_back(T);
  }
  return poses;
}

template <typename P>
ColoredCloud load_pcd(const std::string& path) {
  pcl::PointCloud<P> in;
  ColoredCloud out;
  if (pcl::io::loadPCDFile(path, in) < 0) return out;
  for (const auto& p : in) {
    ColoredPoint q{p.x, p.y, p.z, 128, 128, 128};
    if constexpr (std::is_same_v<P, pcl::PointXYZRGBA>) q.r = p.r, q.g = p.g, q.b = p.b;
    out.push_back(q);
  }
  return finite_points(out);
}

TEST(RgbIcp, Open3dSequencePairwiseWithin2cmAnd1deg) {
  const auto poses = open3d_trajectory();
  if (poses.size() < 5 || open3d_frame(0).empty()) GTEST_SKIP() << "data absent: " << kData << "/rgbd/open3d_testdata";
  RgbIcpOptions o;
  o.voxel_m = 0.02;
  o.feature_radius_m = 0.1;
  o.max_correspondence_m = 0.07;
  for (int i = 0; i + 1 < 5; ++i) {
    const RgbIcpResult r = rgb_icp(open3d_frame(i + 1), open3d_frame(i), Eigen::Isometry3d::Identity(), o);
    const Eigen::Isometry3d truth = poses[size_t(i)].inverse() * poses[size_t(i + 1)];
    const Eigen::Isometry3d err = truth.inverse() * r.T_target_source;
    std::printf("open3d %d->%d: fitness %.3f rmse %.4f m, feature inliers %d/%d, %s, error %.4f m %.3f deg\n", i + 1, i,
                r.score, r.rmse_m, r.feature_inliers, r.feature_matches, r.used_prior ? "prior" : "ransac",
                err.translation().norm(), rotation_deg(err));
    EXPECT_TRUE(r.converged) << r.reason;
    EXPECT_LE(err.translation().norm(), 0.02);
    EXPECT_LE(rotation_deg(err), 1.0);
  }
}

TEST(RgbIcp, BunnyKnownMotionAndPartialViews) {
  const ColoredCloud bun0 = load_pcd<pcl::PointXYZ>(kData + "/pointclouds/pcl_test/bun0.pcd");
  const ColoredCloud bun4 = load_pcd<pcl::PointXYZ>(kData + "/pointclouds/pcl_test/bun4.pcd");
  if (bun0.empty() || bun4.empty()) GTEST_SKIP() << "data absent: " << kData << "/pointclouds/pcl_test/bun0.pcd";
  // Known motion: 20 deg about an oblique axis and 3 cm; the prior is identity, RANSAC must help.
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(20 * M_PI / 180, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  T.translation() << 0.03, -0.01, 0.02;
  RgbIcpOptions o;
  o.voxel_m = 0.004;
  o.feature_radius_m = 0.02;
  o.ransac_inlier_m = 0.005;
  o.max_correspondence_m = 0.01;
  o.colour_scale_m = 0.0;
  const RgbIcpResult r = rgb_icp(transform_cloud(bun0, T), bun0, Eigen::Isometry3d::Identity(), o);
  const Eigen::Isometry3d err = T * r.T_target_source;
  std::printf("bunny known motion: fitness %.3f rmse %.5f, inliers %d, error %.5f m %.3f deg\n", r.score, r.rmse_m,
              r.feature_inliers, err.translation().norm(), rotation_deg(err));
  EXPECT_TRUE(r.converged) << r.reason;
  EXPECT_FALSE(r.used_prior);
  EXPECT_LT(err.translation().norm(), 0.002);
  EXPECT_LT(rotation_deg(err), 0.5);
  // Two partial views (bun0 / bun4, different scans): report the overlap.
  const RgbIcpResult p = rgb_icp(bun4, bun0, Eigen::Isometry3d::Identity(), o);
  std::printf("bunny bun4->bun0: converged %d fitness %.3f rmse %.5f, inliers %d (%s)\n", p.converged, p.score,
              p.rmse_m, p.feature_inliers, p.reason.c_str());
  RecordProperty("bun4_bun0_fitness", std::to_string(p.score));
  EXPECT_GT(p.score, 0.3);
}

TEST(RgbIcp, MilkCartonFoundInKinectScene) {
  const std::string dir = kData + "/pointclouds/pcl_test/";
  const ColoredCloud model = load_pcd<pcl::PointXYZRGBA>(dir + "milk_color.pcd");
  const ColoredCloud scene = load_pcd<pcl::PointXYZRGBA>(dir + "milk_cartoon_all_small_clorox.pcd");
  if (model.empty() || scene.empty()) GTEST_SKIP() << "data absent: " << dir << "milk_color.pcd";
  // The model is cut from the scene (same coordinates): move it away and find it again.
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitY()).toRotationMatrix();
  T.translation() << 0.15, 0.0, -0.1;
  RgbIcpOptions o;
  o.voxel_m = 0.008;
  o.feature_radius_m = 0.04;
  o.ransac_iterations = 20000;
  o.ransac_inlier_m = 0.012;
  o.max_correspondence_m = 0.02;
  const RgbIcpResult r = rgb_icp(transform_cloud(model, T), scene, Eigen::Isometry3d::Identity(), o);
  const Eigen::Isometry3d err = T * r.T_target_source;
  std::printf("milk in scene: fitness %.3f rmse %.4f, inliers %d/%d, error %.4f m %.3f deg\n", r.score, r.rmse_m,
              r.feature_inliers, r.feature_matches, err.translation().norm(), rotation_deg(err));
  EXPECT_TRUE(r.converged) << r.reason;
  EXPECT_GT(r.score, 0.8);
  EXPECT_LT(err.translation().norm(), 0.02);
  EXPECT_LT(rotation_deg(err), 2.0);
}

TEST(RgbIcp, PclGrabberFramesRegisteredWithFitness) {
  const std::string dir = kData + "/pointclouds/pcl_test/grabber_sequences/pcd/";
  if (!std::filesystem::exists(dir)) GTEST_SKIP() << "data absent: " << dir;
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(dir)) files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 3u);
  RgbIcpOptions o;
  o.voxel_m = 0.02;
  o.feature_radius_m = 0.1;
  o.max_correspondence_m = 0.05;
  o.max_iterations = 100;
  o.delta_translation_m = 1e-4;
  o.delta_rotation_rad = 1e-4;
  for (size_t i = 0; i + 1 < files.size(); ++i) {
    const RgbIcpResult r = rgb_icp(load_pcd<pcl::PointXYZRGBA>(files[i + 1]), load_pcd<pcl::PointXYZRGBA>(files[i]),
                                   Eigen::Isometry3d::Identity(), o);
    std::printf("grabber %zu->%zu: converged %d fitness %.3f rmse %.4f m, motion %.4f m %.3f deg\n", i + 1, i,
                r.converged, r.score, r.rmse_m, r.T_target_source.translation().norm(),
                rotation_deg(r.T_target_source));
    RecordProperty("grabber_fitness_" + std::to_string(i), std::to_string(r.score));
    EXPECT_TRUE(r.converged) << r.reason;
    EXPECT_GT(r.score, 0.8);
  }
}

TEST(RgbIcp, BadInputGivesAReason) {
  const RgbIcpResult empty = rgb_icp({}, {{0, 0, 0, 1, 1, 1}});
  EXPECT_FALSE(empty.converged);
  EXPECT_FALSE(empty.reason.empty());
  ColoredCloud plane;
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 30; ++j) plane.push_back(ColoredPoint{0.02f * i, 0.02f * j, 1.0f, 100, 100, 100});
  RgbIcpOptions o;
  o.use_features = false;
  const RgbIcpResult flat = rgb_icp(plane, plane, Eigen::Isometry3d::Identity(), o);  // sliding is unobservable
  EXPECT_FALSE(flat.converged);
  EXPECT_NE(flat.reason.find("degenerate"), std::string::npos);
  ColoredCloud nan_cloud = plane;
  nan_cloud[0].x = std::numeric_limits<float>::quiet_NaN();
  Eigen::Isometry3d bad = Eigen::Isometry3d::Identity();
  bad.translation().x() = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(rgb_icp(nan_cloud, plane, bad, o).converged);
}

}  // namespace
}  // namespace cairn::agent
