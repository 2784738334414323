#pragma once
// Discrete wavelet transform (seed paper Sec. 3.1, Eqs. 14-18 sampled at a = 2^-j, b = k 2^-j):
// orthogonal two-channel filter banks (Haar, Daubechies D4 = "db2" with 4 taps, Daubechies db4
// with 8 taps) with periodic extension, so the inverse reconstructs exactly (to rounding). 2D
// transforms are separable (rows then columns), Mallat layout: after one level the top-left
// quarter holds the approximation (LL), the others the details (LH, HL, HH). Used to fuse colour
// and depth saliency maps (object_detector). Pure C++, no OpenCV.
#include <string>
#include <vector>

namespace cairn::agent {

enum class WaveletType { kHaar, kDaubechies4Tap, kDaubechies8Tap };

/// A dense row-major image of doubles.
struct ImageD {
  int rows = 0, cols = 0;
  std::vector<double> data;
  ImageD() = default;
  ImageD(int r, int c, double v = 0.0) : rows(r), cols(c), data(size_t(r) * size_t(c), v) {}
  double& at(int r, int c) { return data[size_t(r) * size_t(cols) + size_t(c)]; }
  double at(int r, int c) const { return data[size_t(r) * size_t(cols) + size_t(c)]; }
};

/// Low-pass decomposition filter h (the high-pass is g[k] = (-1)^k h[L-1-k]).
std::vector<double> wavelet_lowpass(WaveletType type);

/// One level, 1D: n even, out = [approximation (n/2) | detail (n/2)]. Empty on odd/too-short n.
std::vector<double> dwt_1d(const std::vector<double>& x, WaveletType type);
std::vector<double> idwt_1d(const std::vector<double>& coeffs, WaveletType type);

struct Dwt2dResult {
  ImageD coeffs;  ///< Mallat layout, `levels` levels
  int levels = 0;
  bool converged = false;
  std::string reason;
};

/// `levels` levels; rows and cols must be divisible by 2^levels.
Dwt2dResult dwt_2d(const ImageD& image, int levels, WaveletType type);
/// Inverse of dwt_2d (same levels and type).
ImageD idwt_2d(const ImageD& coeffs, int levels, WaveletType type);

/// Wavelet image fusion: average the approximations, keep the detail coefficient with the larger
/// magnitude, invert. Both images must have the same size (divisible by 2^levels).
Dwt2dResult fuse_wavelet(const ImageD& a, const ImageD& b, int levels, WaveletType type);

}  // namespace cairn::agent
