#include "robot_agent/core/object_detector.h"

#include <algorithm>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "robot_agent/core/cloud_filter.h"

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
      const size_t i = size_t(v) * K.width + u;
      const double z = f.depth[i] * K.depth_scale_m;
      if (f.depth[i] == 0 || z < o.min_depth_m || z > o.max_depth_m) continue;
      PixelPoint pp;
      pp.p_camera = Eigen::Vector3d((u - K.cx) * z / K.fx, (v - K.cy) * z / K.fy, z);
      pp.colour.r = f.rgb[3 * i];
      pp.colour.g = f.rgb[3 * i + 1];
      pp.colour.b = f.rgb[3 * i + 2];
      pts.push_back(pp);
    }
  }
  return pts;
}

// Keeps points near the median depth, moves them to the base frame, fills centroid and cloud.
bool build_cloud(const RgbdFrame& f, std::vector<PixelPoint> pts, const ObjectDetectorOptions& o, Detection* d) {
  if (int(pts.size()) < o.min_points) return false;
  std::vector<double> depths(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) depths[i] = pts[i].p_camera.z();
  std::nth_element(depths.begin(), depths.begin() + depths.size() / 2, depths.end());
  d->median_depth_m = depths[depths.size() / 2];
  ColoredCloud cloud;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const PixelPoint& pp : pts) {
    if (std::abs(pp.p_camera.z() - d->median_depth_m) > o.depth_inlier_m) continue;
    const Eigen::Vector3d p = f.T_base_camera * pp.p_camera;
    sum += p;
    ColoredPoint c = pp.colour;
    c.x = float(p.x());
    c.y = float(p.y());
    c.z = float(p.z());
    cloud.push_back(c);
  }
  if (int(cloud.size()) < o.min_points) return false;
  d->centroid_base = sum / double(cloud.size());
  d->cloud_base = voxel_downsample(cloud, o.voxel_m);
  return true;
}

}  // namespace

std::vector<ObjectClassOptions> default_object_classes() {
  return {
      {"victim", {HsvRange{0, 120, 70, 16, 255, 255}, HsvRange{170, 120, 70, 180, 255, 255}}, 150},
      {"hazard", {HsvRange{20, 120, 70, 35, 255, 255}}, 150},
      {"exit", {HsvRange{45, 80, 50, 85, 255, 255}}, 150},
  };
}

ObjectDetector::ObjectDetector(const ObjectDetectorOptions& options) : options_(options) {}

std::vector<Detection> ObjectDetector::detect(const RgbdFrame& frame) const {
  std::vector<Detection> out;
  if (!frame.valid()) return out;
  const int w = frame.intrinsics.width, h = frame.intrinsics.height;
  const cv::Mat rgb(h, w, CV_8UC3, const_cast<uint8_t*>(frame.rgb.data()));
  cv::Mat hsv;
  cv::cvtColor(rgb, hsv, cv::COLOR_RGB2HSV);
  for (const ObjectClassOptions& cls : options_.classes) {
    const cv::Mat mask = class_mask(hsv, cls, options_.open_kernel_px);
    cv::Mat labels, stats, centroids;
    const int n = cv::connectedComponentsWithStats(mask, labels, stats, centroids, 8, CV_32S);
    for (int label = 1; label < n; ++label) {
      const int area = stats.at<int>(label, cv::CC_STAT_AREA);
      if (area < cls.min_area_px) continue;
      const cv::Rect box(stats.at<int>(label, cv::CC_STAT_LEFT), stats.at<int>(label, cv::CC_STAT_TOP),
                         stats.at<int>(label, cv::CC_STAT_WIDTH), stats.at<int>(label, cv::CC_STAT_HEIGHT));
      Detection d;
      d.class_name = cls.class_name;
      d.bbox_x = box.x;
      d.bbox_y = box.y;
      d.bbox_w = box.width;
      d.bbox_h = box.height;
      d.area_px = area;
      if (!build_cloud(frame, back_project(frame, labels, label, box, options_), options_, &d)) continue;
      d.thumbnail_jpeg = make_thumbnail(rgb, box, options_);
      out.push_back(std::move(d));
    }
  }
  return out;
}

}  // namespace cairn::agent
