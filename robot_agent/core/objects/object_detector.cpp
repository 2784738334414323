#include "robot_agent/core/objects/object_detector.h"

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "common/robot_markers.h"
#include "robot_agent/core/objects/cloud_filter.h"

namespace cairn::agent {
namespace {

cv::Mat class_mask(const cv::Mat& hsv, const ObjectClassOptions& cls, int open_kernel_px) {
  cv::Mat mask = cv::Mat::zeros(hsv.size(), CV_8UC1), part;
  for (const HsvRange& r : cls.ranges) {
    cv::inRange(hsv, cv::Scalar(r.h_lo, r.s_lo, r.v_lo), cv::Scalar(r.h_hi, r.s_hi, r.v_hi), part);
    mask |= part;
  }
  if (open_kernel_px > 1) {
    const cv::Mat k = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(open_kernel_px, open_kernel_px));
    cv::morphologyEx(mask, mask, cv::MORPH_OPEN, k);
  }
  return mask;
}

std::vector<uint8_t> make_thumbnail(const cv::Mat& rgb, const cv::Rect& box, const ObjectDetectorOptions& o) {
  cv::Mat crop = rgb(box), small, bgr;
  const int long_side = std::max(box.width, box.height);
  const double scale = long_side > o.thumbnail_max_px ? double(o.thumbnail_max_px) / long_side : 1.0;
  cv::resize(crop, small, cv::Size(), scale, scale, cv::INTER_AREA);
  cv::cvtColor(small, bgr, cv::COLOR_RGB2BGR);
  std::vector<uint8_t> jpeg;
  cv::imencode(".jpg", bgr, jpeg, {cv::IMWRITE_JPEG_QUALITY, o.thumbnail_jpeg_quality});
  return jpeg;
}

struct PixelPoint {
  Eigen::Vector3d p_camera;
  ColoredPoint colour;
};

// Back-projects the blob's pixels with valid depth: p = depth * K^-1 [u v 1].
std::vector<PixelPoint> back_project(const RgbdFrame& f, const cv::Mat& labels, int label, const cv::Rect& box,
                                     const ObjectDetectorOptions& o) {
  std::vector<PixelPoint> pts;
  const CameraIntrinsics& K = f.intrinsics;
  for (int v = box.y; v < box.y + box.height; ++v) {
    for (int u = box.x; u < box.x + box.width; ++u) {
      if (labels.at<int>(v, u) != label) continue;
      const size_t i = size_t(v) * size_t(K.width) + size_t(u);
      const double z = f.depth[i] * K.depth_scale_m;
      if (f.depth[i] == 0 || !(z >= o.min_depth_m && z <= o.max_depth_m)) continue;
      PixelPoint pp;
      pp.p_camera = Eigen::Vector3d((u - K.cx) * z / K.fx, (v - K.cy) * z / K.fy, z);
      pp.colour = ColoredPoint{0, 0, 0, f.rgb[3 * i], f.rgb[3 * i + 1], f.rgb[3 * i + 2]};
      pts.push_back(pp);
    }
  }
  return pts;
}

// Keeps points near the median depth, moves them to the base frame, filters, fits the centre.
bool build_cloud(const RgbdFrame& f, std::vector<PixelPoint> pts, const ObjectDetectorOptions& o,
                 const ObjectClassOptions& cls, Detection* d) {
  if (int(pts.size()) < o.min_points) return false;
  std::vector<double> depths(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) depths[i] = pts[i].p_camera.z();
  std::nth_element(depths.begin(), depths.begin() + long(depths.size() / 2), depths.end());
  d->median_depth_m = depths[depths.size() / 2];
  ColoredCloud cloud;
  for (const PixelPoint& pp : pts) {
    if (std::abs(pp.p_camera.z() - d->median_depth_m) > o.depth_inlier_m) continue;
    const Eigen::Vector3d p = f.T_base_camera * pp.p_camera;
    cloud.push_back(ColoredPoint{float(p.x()), float(p.y()), float(p.z()), pp.colour.r, pp.colour.g, pp.colour.b});
  }
  cloud = voxel_downsample(cloud, o.voxel_m);
  if (o.outlier_neighbours > 0) cloud = remove_outliers(cloud, o.outlier_neighbours, o.outlier_stddev);
  if (int(cloud.size()) < o.min_points) return false;
  std::vector<Eigen::Vector3d> xyz;
  xyz.reserve(cloud.size());
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const ColoredPoint& c : cloud) xyz.emplace_back(c.x, c.y, c.z), sum += xyz.back();
  d->surface_centroid_base = sum / double(cloud.size());
  d->centroid_base = d->surface_centroid_base;
  if (o.fit_shape) {
    ShapeFitOptions fit;
    // A view cut by the image border shows an unknown part of the face: only the short side is safe.
    fit.box_footprint_prior_m =
        d->truncated_side ? Eigen::Vector2d::Constant(cls.box_footprint_m.minCoeff()) : cls.box_footprint_m;
    d->shape = best_shape_fit(xyz, d->camera_base, fit);
    if (d->shape.converged) d->centroid_base = d->shape.center_m;
  }
  d->cloud_base = std::move(cloud);
  return true;
}

// Eq. 19 fallback: the floor contact point under the blob's bottom centre.
// The contact point is the object's near edge: the centre is about half its short side further on.
bool place_without_depth(const RgbdFrame& f, const cv::Rect& box, const ObjectClassOptions& cls, Detection* d) {
  const auto H = ground_homography(f.intrinsics, f.T_base_camera);
  if (!H) return false;
  const auto xy = apply_homography(*H, box.x + 0.5 * box.width, box.y + box.height - 0.5);
  if (!xy) return false;
  d->has_depth = false;
  d->centroid_base = Eigen::Vector3d(xy->x(), xy->y(), 0.0);
  Eigen::Vector3d ray = d->centroid_base - d->camera_base;
  ray.z() = 0.0;
  if (ray.norm() > 1e-6) d->centroid_base += 0.5 * std::max(0.0, cls.box_footprint_m.minCoeff()) * ray.normalized();
  d->surface_centroid_base = d->centroid_base;
  d->median_depth_m = (d->centroid_base - d->camera_base).norm();
  return true;
}

double blob_saliency(const ImageD& sal, int sal_w, int sal_h, const cv::Mat& labels, int label, const cv::Rect& box) {
  if (sal.data.empty()) return 0.0;
  double sum = 0.0;
  int n = 0;
  const double sx = double(sal_w) / labels.cols, sy = double(sal_h) / labels.rows;
  for (int v = box.y; v < box.y + box.height; v += 2)
    for (int u = box.x; u < box.x + box.width; u += 2)
      if (labels.at<int>(v, u) == label) {
        sum += sal.at(std::min(sal_h - 1, int(v * sy)), std::min(sal_w - 1, int(u * sx)));
        ++n;
      }
  return n ? sum / n : 0.0;
}

}  // namespace

std::vector<ObjectClassOptions> default_object_classes() {
  std::vector<ObjectClassOptions> classes = {
      {"victim",
       {HsvRange{0, 120, 70, 16, 255, 255}, HsvRange{170, 120, 70, 180, 255, 255}},
       150,
       0.3,
       12.0,
       Eigen::Vector2d(1.6, 0.5)},
      {"hazard", {HsvRange{20, 120, 70, 35, 255, 255}}, 150, 0.3, 12.0, Eigen::Vector2d::Zero()},
      {"exit", {HsvRange{45, 80, 50, 85, 255, 255}}, 150, 0.3, 12.0, Eigen::Vector2d(1.0, 0.12)},
  };
  const std::vector<ObjectClassOptions> markers = robot_marker_classes();
  classes.insert(classes.end(), markers.begin(), markers.end());
  return classes;
}

std::vector<ObjectClassOptions> robot_marker_classes() {
  std::vector<ObjectClassOptions> out;
  for (const RobotMarker& m : kRobotMarkers) {
    out.push_back({robot_marker_class(m.robot),
                   {HsvRange{m.hue - 7, 120, 40, m.hue + 7, 255, 255}},
                   150,
                   0.3,
                   12.0,
                   Eigen::Vector2d::Zero()});
  }
  return out;
}

std::string robot_marker_class(RobotId robot) { return "robot marker " + std::to_string(robot.value); }

std::optional<RobotId> robot_of_marker_class(const std::string& class_name) {
  for (const RobotMarker& m : kRobotMarkers) {
    if (class_name == robot_marker_class(m.robot)) return m.robot;
  }
  return std::nullopt;
}

ObjectDetector::ObjectDetector(const ObjectDetectorOptions& options) : options_(options) {}

DetectionFrame ObjectDetector::analyse(const RgbdFrame& frame) const {
  DetectionFrame out;
  if (!frame.valid()) return out.reason = "invalid frame: image and depth sizes disagree", out;
  const int w = frame.intrinsics.width, h = frame.intrinsics.height;
  const double scale = double(w) * h / (320.0 * 240.0);
  std::vector<uint8_t> sharp;
  if (options_.sharpen) sharp = sharpen_eq13(frame.rgb, w, h);
  const cv::Mat rgb(h, w, CV_8UC3, const_cast<uint8_t*>(sharp.empty() ? frame.rgb.data() : sharp.data()));
  const cv::Mat rgb_raw(h, w, CV_8UC3, const_cast<uint8_t*>(frame.rgb.data()));
  cv::Mat hsv;
  cv::cvtColor(rgb, hsv, cv::COLOR_RGB2HSV);
  if (options_.use_saliency) out.saliency = saliency_maps(frame, options_.saliency);
  const ImageD& sal = out.saliency.fused;
  const int sal_w = out.saliency.width, sal_h = out.saliency.height;
  const int open_px = std::max(1, int(std::lround(options_.open_kernel_px * std::sqrt(scale))));
  const Eigen::Vector3d camera = frame.T_base_camera.translation();
  for (const ObjectClassOptions& cls : options_.classes) {
    const cv::Mat mask = class_mask(hsv, cls, open_px);
    cv::Mat labels, stats, centroids;
    const int n = cv::connectedComponentsWithStats(mask, labels, stats, centroids, 8, CV_32S);
    for (int label = 1; label < n; ++label) {
      const int area = stats.at<int>(label, cv::CC_STAT_AREA);
      if (area < cls.min_area_px * scale) continue;
      ++out.blobs;
      const cv::Rect box(stats.at<int>(label, cv::CC_STAT_LEFT), stats.at<int>(label, cv::CC_STAT_TOP),
                         stats.at<int>(label, cv::CC_STAT_WIDTH), stats.at<int>(label, cv::CC_STAT_HEIGHT));
      Detection d;
      d.class_name = cls.class_name;
      d.bbox_x = box.x, d.bbox_y = box.y, d.bbox_w = box.width, d.bbox_h = box.height;
      d.area_px = area;
      d.fill_ratio = double(area) / double(box.area());
      const double aspect = double(std::max(box.width, box.height)) / std::max(1, std::min(box.width, box.height));
      d.circularity = 4.0 * area / (M_PI * std::pow(std::max(box.width, box.height), 2));
      if (d.fill_ratio < cls.min_fill_ratio || aspect > cls.max_aspect) {
        ++out.rejected_shape;
        continue;
      }
      d.camera_base = camera;
      d.truncated_side = box.x <= 1 || box.x + box.width >= w - 1;
      d.truncated_top_bottom = box.y <= 1 || box.y + box.height >= h - 1;
      d.saliency = blob_saliency(sal, sal_w, sal_h, labels, label, box);
      if (!build_cloud(frame, back_project(frame, labels, label, box, options_), options_, cls, &d)) {
        if (!place_without_depth(frame, box, cls, &d)) continue;
        ++out.without_depth;
      }
      d.thumbnail_jpeg = make_thumbnail(rgb_raw, box, options_);
      out.detections.push_back(std::move(d));
    }
  }
  out.converged = true;
  if (out.without_depth)
    out.reason = "no valid depth on " + std::to_string(out.without_depth) + " blob(s): placed by the ground homography";
  return out;
}

}  // namespace cairn::agent
