#include "robot_agent/core/objects/saliency.h"

#include <Eigen/Dense>
#include <algorithm>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace cairn::agent {

std::vector<uint8_t> sharpen_eq13(const std::vector<uint8_t>& rgb, int width, int height) {
  if (width <= 0 || height <= 0 || rgb.size() != size_t(width) * size_t(height) * 3) return {};
  const cv::Mat in(height, width, CV_8UC3, const_cast<uint8_t*>(rgb.data()));
  const cv::Mat kernel = (cv::Mat_<float>(3, 3) << 0, -1, 0, -1, 5, -1, 0, -1, 0);
  std::vector<uint8_t> out(rgb.size());
  cv::Mat result(height, width, CV_8UC3, out.data());
  cv::filter2D(in, result, in.depth(), kernel);  // Table II: filter2D(image, result, image.depth(), kernel)
  return out;
}

SaliencyMaps saliency_maps(const RgbdFrame& f, const SaliencyOptions& o) {
  if (!f.valid() || o.downsample < 1) return {};
  const int mult = o.downsample << o.levels;
  const int w = (f.intrinsics.width / mult) * (1 << o.levels), h = (f.intrinsics.height / mult) * (1 << o.levels);
  if (w <= 0 || h <= 0) return {};
  const cv::Mat rgb(f.intrinsics.height, f.intrinsics.width, CV_8UC3, const_cast<uint8_t*>(f.rgb.data()));
  cv::Mat small, hsv, depth_small;
  cv::resize(rgb, small, cv::Size(w, h), 0, 0, cv::INTER_AREA);
  cv::cvtColor(small, hsv, cv::COLOR_RGB2HSV);
  cv::Mat depth(f.intrinsics.height, f.intrinsics.width, CV_16UC1, const_cast<uint16_t*>(f.depth.data()));
  cv::resize(depth, depth_small, cv::Size(w, h), 0, 0, cv::INTER_NEAREST);
  cv::Mat depth_m;
  depth_small.convertTo(depth_m, CV_64F, f.intrinsics.depth_scale_m);
  cv::Mat blurred;
  cv::blur(depth_m, blurred, cv::Size(7, 7));
  ImageD colour(h, w), near(h, w);
  for (int r = 0; r < h; ++r) {
    for (int c = 0; c < w; ++c) {
      const cv::Vec3b px = hsv.at<cv::Vec3b>(r, c);
      colour.at(r, c) = (px[1] / 255.0) * (px[2] / 255.0);
      const double d = depth_m.at<double>(r, c);
      const double valid = d > 0.0 && d < o.max_depth_m;
      const double contrast = valid ? std::min(1.0, std::abs(blurred.at<double>(r, c) - d)) : 0.0;
      near.at(r, c) = valid ? 0.5 * (1.0 - d / o.max_depth_m) + 0.5 * contrast : 0.0;
    }
  }
  Dwt2dResult fused = fuse_wavelet(colour, near, o.levels, o.wavelet);
  if (!fused.converged) return {};
  const auto [lo, hi] = std::minmax_element(fused.coeffs.data.begin(), fused.coeffs.data.end());
  const double span = std::max(1e-12, *hi - *lo), base = *lo;
  for (double& v : fused.coeffs.data) v = (v - base) / span;
  SaliencyMaps out;
  out.fused = std::move(fused.coeffs);
  out.colour = std::move(colour);
  out.width = w, out.height = h;
  return out;
}

// A floor point X = (x, y, 0) in the base frame projects as alpha [u v 1]^T = K [r1 r2 t] [x y 1]^T
// with [R t] = T_camera_base; H of Eq. 19 (pixel -> ground) is the inverse of K [r1 r2 t].
std::optional<Eigen::Matrix3d> ground_homography(const CameraIntrinsics& K, const Eigen::Isometry3d& T_base_camera) {
  if (K.fx <= 0 || K.fy <= 0) return std::nullopt;
  const Eigen::Isometry3d T_cb = T_base_camera.inverse();
  Eigen::Matrix3d Km;
  Km << K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1;
  Eigen::Matrix3d M;
  M << T_cb.linear().col(0), T_cb.linear().col(1), T_cb.translation();
  const Eigen::Matrix3d G = Km * M;
  if (std::abs(G.determinant()) < 1e-12) return std::nullopt;
  return G.inverse();
}

std::optional<Eigen::Vector2d> apply_homography(const Eigen::Matrix3d& H, double u, double v) {
  const Eigen::Vector3d q = H * Eigen::Vector3d(u, v, 1.0);
  if (!(std::abs(q.z()) > 1e-12)) return std::nullopt;
  const Eigen::Vector2d p = q.head<2>() / q.z();
  // The point must be in front of the camera: the pixel ray must hit the floor (alpha > 0 for K M).
  const Eigen::Vector3d back = H.inverse() * Eigen::Vector3d(p.x(), p.y(), 1.0);
  if (!(back.z() > 0.0)) return std::nullopt;
  return p;
}

}  // namespace cairn::agent
