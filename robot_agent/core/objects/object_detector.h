#pragma once
// Detection of objects of interest in RGB-D frames and their coloured 3D clouds (seed paper
// Sec. 2-3): the sharpening kernel of Eq. 13 -> per-class HSV colour ranges -> connected components
// with 2D shape cues (fill ratio, aspect, circularity) -> wavelet-fused colour/depth saliency
// (Eqs. 14-18) as a confidence cue -> depth back-projection (p = z K^-1 [u v 1]) -> voxel filter and
// statistical outlier removal -> primitive fit for the object centre (shape_fit.h). Without valid
// depth the ground homography of Eq. 19 places the blob's floor contact point instead.
// OpenCV and PCL stay inside the .cpp files.
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "common/ids.h"

#include "common/point_cloud.h"
#include "common/sensors.h"
#include "robot_agent/core/objects/saliency.h"
#include "robot_agent/core/objects/shape_fit.h"

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
  int min_area_px = 150;        ///< at 320x240; scaled with the image area
  double min_fill_ratio = 0.3;  ///< blob area / bounding-box area (shape cue)
  double max_aspect = 12.0;     ///< long / short side of the bounding box
  /// Footprint (long, short side) of a box-shaped object of this class; 0: unknown. Completes the
  /// sides a box hides from the camera (shape_fit.h: complete_box_footprint).
  Eigen::Vector2d box_footprint_m = Eigen::Vector2d::Zero();
};

/// victim = red/orange (lying: 1.6 x 0.5 m), hazard = yellow, exit = green (door panel: 1.0 x 0.12 m),
/// then the team's robot markers (robot_marker_classes()).
std::vector<ObjectClassOptions> default_object_classes();
/// One class per marked robot (common/robot_markers.h), named robot_marker_class(id): its hue +- 7.
std::vector<ObjectClassOptions> robot_marker_classes();
std::string robot_marker_class(RobotId robot);
/// The robot whose marker class `class_name` is; nullopt for an object class.
std::optional<RobotId> robot_of_marker_class(const std::string& class_name);

struct ObjectDetectorOptions {
  std::vector<ObjectClassOptions> classes = default_object_classes();
  bool sharpen = true;     ///< Eq. 13 before colour segmentation
  int open_kernel_px = 5;  ///< morphological opening of each class mask (at 320x240)
  double min_depth_m = 0.15;
  double max_depth_m = 10.0;
  double depth_inlier_m = 1.0;  ///< keep points within this of the blob's median depth
  double voxel_m = 0.025;       ///< cloud downsampling
  int outlier_neighbours = 10;  ///< statistical outlier removal (0: off)
  double outlier_stddev = 2.5;
  bool fit_shape = true;  ///< centre from a primitive fit (else the visible centroid)
  int min_points = 10;    ///< blobs with fewer valid depth points use the homography cue
  bool use_saliency = true;
  SaliencyOptions saliency;
  int thumbnail_max_px = 96;  ///< long side of the JPEG thumbnail
  int thumbnail_jpeg_quality = 80;
};

struct Detection {
  std::string class_name;
  int bbox_x = 0, bbox_y = 0, bbox_w = 0, bbox_h = 0;  ///< pixels
  int area_px = 0;
  double fill_ratio = 0.0, circularity = 0.0;  ///< 2D shape cues
  double saliency = 0.0;                       ///< mean fused saliency in the blob, 0..1
  bool has_depth = true;                       ///< false: position from the ground homography only
  bool truncated_side = false;                 ///< blob touches the left/right image border: centre unreliable
  bool truncated_top_bottom = false;           ///< touches the top/bottom border: height unreliable
  double median_depth_m = 0.0;
  Eigen::Vector3d centroid_base = Eigen::Vector3d::Zero();          ///< object centre estimate (base frame)
  Eigen::Vector3d surface_centroid_base = Eigen::Vector3d::Zero();  ///< mean of the visible points
  Eigen::Vector3d camera_base = Eigen::Vector3d::Zero();            ///< viewpoint, for the tracker's noise model
  ShapeFit shape;                                                   ///< base frame
  ColoredCloud cloud_base;                                          ///< voxel-filtered, base frame
  std::vector<uint8_t> thumbnail_jpeg;
};

struct DetectionFrame {
  std::vector<Detection> detections;
  bool converged = false;  ///< the frame was usable
  std::string reason;      ///< why not, or what was degraded ("no valid depth: ...")
  int blobs = 0, rejected_shape = 0, without_depth = 0;
  SaliencyMaps saliency;  ///< the frame's saliency (empty when use_saliency is off)
};

class ObjectDetector {
 public:
  explicit ObjectDetector(const ObjectDetectorOptions& options = {});
  /// Detections in class order, then by blob order (deterministic).
  DetectionFrame analyse(const RgbdFrame& frame) const;
  /// analyse(frame).detections; empty for an invalid frame.
  std::vector<Detection> detect(const RgbdFrame& frame) const { return analyse(frame).detections; }
  const ObjectDetectorOptions& options() const { return options_; }

 private:
  ObjectDetectorOptions options_;
};

}  // namespace cairn::agent
