#include "robot_agent/core/objects/hue_depth.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <set>

namespace cairn::agent {

double jg_hue_deg(double r, double g, double b) {
  const double M = std::max({r, g, b}), m = std::min({r, g, b}), C = M - m;
  if (!(C > 0.0)) return 0.0;
  double h_prime = 0.0;
  if (M == r) {
    h_prime = std::fmod((g - b) / C, 6.0);  // Eq. 11, first case: (G - B)/C mod 6
    if (h_prime < 0.0) h_prime += 6.0;
  } else if (M == g) {
    h_prime = (b - r) / C + 2.0;
  } else {
    h_prime = (r - g) / C + 4.0;
  }
  return 60.0 * h_prime;  // Eq. 12
}

HueDepthFit fit_hue_depth(const std::vector<HueDepthSample>& samples) {
  HueDepthFit fit;
  std::set<double> hues;
  for (const HueDepthSample& s : samples) {
    if (!std::isfinite(s.hue_deg) || !std::isfinite(s.depth_cm)) {
      fit.reason = "non-finite sample";
      return fit;
    }
    hues.insert(s.hue_deg);
  }
  if (hues.size() < 3) {
    fit.reason = "need at least 3 samples with distinct hues, got " + std::to_string(hues.size());
    return fit;
  }
  // Centre and scale H for conditioning, solve, then expand back to a H^2 + b H + c.
  double mean = 0.0;
  for (const HueDepthSample& s : samples) mean += s.hue_deg;
  mean /= double(samples.size());
  const double scale = 100.0;
  Eigen::MatrixXd A(samples.size(), 3);
  Eigen::VectorXd y(samples.size());
  for (size_t i = 0; i < samples.size(); ++i) {
    const double x = (samples[i].hue_deg - mean) / scale;
    A.row(Eigen::Index(i)) << x * x, x, 1.0;
    y(Eigen::Index(i)) = samples[i].depth_cm;
  }
  const Eigen::Vector3d p = A.colPivHouseholderQr().solve(y);
  fit.model.a = p(0) / (scale * scale);
  fit.model.b = p(1) / scale - 2.0 * p(0) * mean / (scale * scale);
  fit.model.c = p(2) - p(1) * mean / scale + p(0) * mean * mean / (scale * scale);
  double sq = 0.0;
  for (const HueDepthSample& s : samples) {
    const double r = fit.model.depth_cm(s.hue_deg) - s.depth_cm;
    sq += r * r;
    fit.max_abs_residual_cm = std::max(fit.max_abs_residual_cm, std::abs(r));
  }
  fit.score = std::sqrt(sq / double(samples.size()));
  fit.converged = fit.model.a == fit.model.a;  // finite
  if (!fit.converged) fit.reason = "degenerate least-squares system";
  return fit;
}

double mean_hue_deg(const std::vector<unsigned char>& rgb, const std::vector<unsigned char>& mask) {
  const size_t n = rgb.size() / 3;
  double sum[3] = {0, 0, 0};
  size_t count = 0;
  for (size_t i = 0; i < n; ++i) {
    if (!mask.empty() && (i >= mask.size() || !mask[i])) continue;
    for (int c = 0; c < 3; ++c) sum[c] += rgb[3 * i + size_t(c)];
    ++count;
  }
  if (count == 0) return -1.0;
  return jg_hue_deg(sum[0] / double(count), sum[1] / double(count), sum[2] / double(count));
}

}  // namespace cairn::agent
