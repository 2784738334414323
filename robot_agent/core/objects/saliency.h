#pragma once
// Image cues of the seed paper used by the detector: the sharpening kernel of Eq. 13 / Algorithm 2
// / Table II (cv::filter2D with [0 -1 0; -1 5 -1; 0 -1 0]), colour and depth saliency maps fused
// by the discrete wavelet transform (Eqs. 14-18, wavelet.h), and the ground-plane homography of
// Eq. 19 (alpha [u' v' 1]^T = H [u v 1]^T) mapping a pixel on the floor to base-frame (x, y) —
// a depth-free position for the contact point of an object (valid on flat floor only).
// OpenCV stays inside saliency.cpp.
#include <Eigen/Geometry>
#include <optional>
#include <vector>

#include "common/sensors.h"
#include "robot_agent/core/objects/wavelet.h"

namespace cairn::agent {

/// Eq. 13 applied to an RGB8 image (per channel, saturated to 0..255).
std::vector<uint8_t> sharpen_eq13(const std::vector<uint8_t>& rgb, int width, int height);

struct SaliencyOptions {
  int downsample = 4;  ///< saliency is computed on a (w/downsample) x (h/downsample) grid
  int levels = 2;
  WaveletType wavelet = WaveletType::kHaar;
  double max_depth_m = 10.0;
};

/// The saliency of one frame on a width x height grid (a downsampled image, row-major).
struct SaliencyMaps {
  ImageD fused;   ///< colour and depth saliency fused by the wavelet transform, normalised per frame to 0..1
  ImageD colour;  ///< HSV saturation x value, 0..1: absolute (a grey frame stays near 0)
  int width = 0, height = 0;
  bool empty() const { return fused.data.empty(); }
};

/// Colour saliency (HSV saturation x value), depth saliency (nearness plus local depth contrast),
/// fused by fuse_wavelet and normalised to 0..1. Empty on bad input.
SaliencyMaps saliency_maps(const RgbdFrame& frame, const SaliencyOptions& options);

/// Eq. 19: the homography from pixel (u, v) to base-frame ground coordinates (x, y, 1) for a camera
/// with intrinsics K mounted at T_base_camera over the plane z = 0. nullopt when the camera
/// looks parallel to the floor's normal or the matrix is singular.
std::optional<Eigen::Matrix3d> ground_homography(const CameraIntrinsics& K, const Eigen::Isometry3d& T_base_camera);

/// Applies Eq. 19; nullopt when alpha <= 0 (the pixel is above the horizon).
std::optional<Eigen::Vector2d> apply_homography(const Eigen::Matrix3d& H, double u, double v);

}  // namespace cairn::agent
