#include "robot_agent/core/objects/wavelet.h"

#include <cmath>

namespace cairn::agent {
namespace {

std::vector<double> highpass(const std::vector<double>& h) {
  const size_t L = h.size();
  std::vector<double> g(L);
  for (size_t k = 0; k < L; ++k) g[k] = ((k % 2) ? -1.0 : 1.0) * h[L - 1 - k];
  return g;
}

// Applies f to every row (axis 0) or column (axis 1) of the top-left rows x cols block.
template <typename F>
void apply_lines(ImageD* img, int rows, int cols, bool along_rows, F f) {
  const int lines = along_rows ? rows : cols, n = along_rows ? cols : rows;
  std::vector<double> line(static_cast<size_t>(n));
  for (int l = 0; l < lines; ++l) {
    for (int i = 0; i < n; ++i) line[size_t(i)] = along_rows ? img->at(l, i) : img->at(i, l);
    const std::vector<double> out = f(line);
    for (int i = 0; i < n; ++i) (along_rows ? img->at(l, i) : img->at(i, l)) = out[size_t(i)];
  }
}

bool divisible(const ImageD& im, int levels) {
  if (levels < 1 || levels > 16) return false;
  const int d = 1 << levels;
  return im.rows >= d && im.cols >= d && im.rows % d == 0 && im.cols % d == 0 &&
         im.data.size() == size_t(im.rows) * size_t(im.cols);
}

}  // namespace

std::vector<double> wavelet_lowpass(WaveletType type) {
  switch (type) {
    case WaveletType::kHaar:
      return {M_SQRT1_2, M_SQRT1_2};
    case WaveletType::kDaubechies4Tap: {
      const double s3 = std::sqrt(3.0), d = 4.0 * std::sqrt(2.0);
      return {(1 + s3) / d, (3 + s3) / d, (3 - s3) / d, (1 - s3) / d};
    }
    case WaveletType::kDaubechies8Tap:
      return {0.23037781330885523,  0.7148465705525415,   0.6308807679295904,   -0.02798376941698385,
              -0.18703481171888114, 0.030841381835986965, 0.032883011666982945, -0.010597401784997278};
  }
  return {};
}

// a[k] = sum_i h[i] x[(2k + i) mod n], d[k] = sum_i g[i] x[(2k + i) mod n]  (periodic extension).
std::vector<double> dwt_1d(const std::vector<double>& x, WaveletType type) {
  const size_t n = x.size();
  if (n < 2 || n % 2) return {};
  const std::vector<double> h = wavelet_lowpass(type), g = highpass(h);
  std::vector<double> out(n, 0.0);
  for (size_t k = 0; k < n / 2; ++k) {
    for (size_t i = 0; i < h.size(); ++i) {
      const double v = x[(2 * k + i) % n];
      out[k] += h[i] * v;
      out[n / 2 + k] += g[i] * v;
    }
  }
  return out;
}

// Orthogonality: x = A^T a + G^T d, i.e. x[(2k + i) mod n] += h[i] a[k] + g[i] d[k].
std::vector<double> idwt_1d(const std::vector<double>& c, WaveletType type) {
  const size_t n = c.size();
  if (n < 2 || n % 2) return {};
  const std::vector<double> h = wavelet_lowpass(type), g = highpass(h);
  std::vector<double> x(n, 0.0);
  for (size_t k = 0; k < n / 2; ++k) {
    for (size_t i = 0; i < h.size(); ++i) x[(2 * k + i) % n] += h[i] * c[k] + g[i] * c[n / 2 + k];
  }
  return x;
}

Dwt2dResult dwt_2d(const ImageD& image, int levels, WaveletType type) {
  Dwt2dResult r;
  if (!divisible(image, levels)) {
    r.reason = "image size must be divisible by 2^levels";
    return r;
  }
  r.coeffs = image;
  r.levels = levels;
  int rows = image.rows, cols = image.cols;
  auto fwd = [type](const std::vector<double>& v) { return dwt_1d(v, type); };
  for (int l = 0; l < levels; ++l, rows /= 2, cols /= 2) {
    apply_lines(&r.coeffs, rows, cols, true, fwd);
    apply_lines(&r.coeffs, rows, cols, false, fwd);
  }
  r.converged = true;
  return r;
}

ImageD idwt_2d(const ImageD& coeffs, int levels, WaveletType type) {
  if (!divisible(coeffs, levels)) return {};
  ImageD out = coeffs;
  auto inv = [type](const std::vector<double>& v) { return idwt_1d(v, type); };
  for (int l = levels - 1; l >= 0; --l) {
    const int rows = coeffs.rows >> l, cols = coeffs.cols >> l;
    apply_lines(&out, rows, cols, false, inv);
    apply_lines(&out, rows, cols, true, inv);
  }
  return out;
}

Dwt2dResult fuse_wavelet(const ImageD& a, const ImageD& b, int levels, WaveletType type) {
  Dwt2dResult r;
  if (a.rows != b.rows || a.cols != b.cols) {
    r.reason = "fused images differ in size";
    return r;
  }
  Dwt2dResult ca = dwt_2d(a, levels, type), cb = dwt_2d(b, levels, type);
  if (!ca.converged || !cb.converged) {
    r.reason = ca.converged ? cb.reason : ca.reason;
    return r;
  }
  const int ar = a.rows >> levels, ac = a.cols >> levels;
  ImageD fused(a.rows, a.cols);
  for (int i = 0; i < a.rows; ++i) {
    for (int j = 0; j < a.cols; ++j) {
      const double x = ca.coeffs.at(i, j), y = cb.coeffs.at(i, j);
      fused.at(i, j) = (i < ar && j < ac) ? 0.5 * (x + y) : (std::abs(x) >= std::abs(y) ? x : y);
    }
  }
  r.coeffs = idwt_2d(fused, levels, type);
  r.levels = levels;
  r.converged = true;
  return r;
}

}  // namespace cairn::agent
