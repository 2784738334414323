#pragma once
// Colour-based detection of objects of interest in RGB-D frames and their coloured 3D clouds
// (seed paper Sec. 2-3, first version: HSV thresholds -> connected components -> depth
// back-projection -> voxel filter). OpenCV and PCL stay inside the .cpp files.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "common/point_cloud.h"
#include "common/sensors.h"

namespace cairn::agent {

/// Inclusive HSV bounds in OpenCV's 8-bit convention: H 0..180, S and V 0..255.
struct HsvRange {
  int h_lo = 0, s_lo = 0, v_lo = 0;
  int h_hi = 180, s_hi = 255, v_hi = 255;
};

/// One object class; its mask is the union of its ranges (red needs two: hue wraps at 180).
struct ObjectClassOptions {
  std::string class_name;
  std::vector<HsvRange> ranges;
  int min_area_px = 150;
};

/// victim = red/orange, hazard = yellow, exit = green.
std::vector<ObjectClassOptions> default_object_classes();

struct ObjectDetectorOptions {
  std::vector<ObjectClassOptions> classes = default_object_classes();
  int open_kernel_px = 5;          ///< morphological opening of each class mask
  double min_depth_m = 0.15;
  double max_depth_m = 10.0;
  double depth_inlier_m = 0.3;     ///< keep points within this of the blob's median depth
  double voxel_m = 0.025;          ///< cloud downsampling
  int min_points = 10;             ///< blobs with fewer valid depth points are dropped
  int thumbnail_max_px = 96;       ///< long side of the JPEG thumbnail
  int thumbnail_jpeg_quality = 80;
};

struct Detection {
  std::string class_name;
  int bbox_x = 0, bbox_y = 0, bbox_w = 0, bbox_h = 0;  ///< pixels
  int area_px = 0;
  double median_depth_m = 0.0;
  Eigen::Vector3d centroid_base = Eigen::Vector3d::Zero();  ///< mean of the inlier points
  ColoredCloud cloud_base;                                   ///< voxel-filtered, base frame
  std::vector<uint8_t> thumbnail_jpeg;
};

class ObjectDetector {
 public:
  explicit ObjectDetector(const ObjectDetectorOptions& options = {});
  /// Detections in class order, then by blob order (deterministic). Empty for an invalid frame.
  std::vector<Detection> detect(const RgbdFrame& frame) const;

 private:
  ObjectDetectorOptions options_;
};

}  // namespace cairn::agent
