#include "robot_agent/core/correlative_scan_matcher.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace cairn::agent {
namespace {

double max_range_m(const std::vector<Eigen::Vector2f>& points) {
  double r = 0.0;
  for (const auto& p : points) r = std::max(r, double(p.norm()));
  return r;
}

// out[k] += in[k] for k < n (SSE2: 16 or 8 cells per step; the same integer sums as the scalar loop).
[[maybe_unused]] inline void add_row(const uint8_t* in, uint32_t* out, int n) {
  int k = 0;
#if defined(__SSE2__)
  const __m128i zero = _mm_setzero_si128();
  for (; k + 16 <= n; k += 16) {
    const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(in + k));
    const __m128i lo = _mm_unpacklo_epi8(v, zero), hi = _mm_unpackhi_epi8(v, zero);
    __m128i* o = reinterpret_cast<__m128i*>(out + k);
    _mm_storeu_si128(o + 0, _mm_add_epi32(_mm_loadu_si128(o + 0), _mm_unpacklo_epi16(lo, zero)));
    _mm_storeu_si128(o + 1, _mm_add_epi32(_mm_loadu_si128(o + 1), _mm_unpackhi_epi16(lo, zero)));
    _mm_storeu_si128(o + 2, _mm_add_epi32(_mm_loadu_si128(o + 2), _mm_unpacklo_epi16(hi, zero)));
    _mm_storeu_si128(o + 3, _mm_add_epi32(_mm_loadu_si128(o + 3), _mm_unpackhi_epi16(hi, zero)));
  }
  if (k + 8 <= n) {
    const __m128i lo = _mm_unpacklo_epi8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(in + k)), zero);
    __m128i* o = reinterpret_cast<__m128i*>(out + k);
    _mm_storeu_si128(o + 0, _mm_add_epi32(_mm_loadu_si128(o + 0), _mm_unpacklo_epi16(lo, zero)));
    _mm_storeu_si128(o + 1, _mm_add_epi32(_mm_loadu_si128(o + 1), _mm_unpackhi_epi16(lo, zero)));
    k += 8;
  }
#endif
  for (; k < n; ++k) out[k] += in[k];
}

// Adds, for every translation offset (dx, dy) in [-n, n]^2, the field value at cell + offset of each
// point to scores[(dy + n) * side + dx + n]. Rows are read contiguously; out-of-grid reads 0.
[[maybe_unused]] void accumulate_u32(const Eigen::Vector2i* cells, size_t num_cells, int n, const ProbabilityGrid& grid,
                                     uint32_t* base) {
  const int side = 2 * n + 1;
  const uint8_t* values = grid.field().data();
  const int w = grid.width(), h = grid.height();
  for (size_t i = 0; i < num_cells; ++i) {
    const Eigen::Vector2i& c = cells[i];
    const bool inside = c.x() - n >= 0 && c.y() - n >= 0 && c.x() + n < w && c.y() + n < h;
    if (inside) {
      const uint8_t* row = values + size_t(c.y() - n) * w + (c.x() - n);
      uint32_t* out = base;
      for (int dy = 0; dy < side; ++dy, row += w, out += side) add_row(row, out, side);
      continue;
    }
    // Clip the window to the grid.
    const int k0 = std::max(0, n - c.x()), k1 = std::min(side, w - (c.x() - n));
    const int d0 = std::max(0, n - c.y()), d1 = std::min(side, h - (c.y() - n));
    for (int dy = d0; dy < d1; ++dy) {
      const uint8_t* row = values + size_t(c.y() - n + dy) * w + (c.x() - n);
      uint32_t* out = base + size_t(dy) * side;
      if (k1 > k0) add_row(row + k0, out + k0, k1 - k0);
    }
  }
}

#if defined(__SSE2__)
// At most this many points are summed in 16 bits (255 * 257 = 65535).
constexpr size_t kMaxPointsU16 = 257;

// Adds `side` field rows (pitch w) of kBlocks * 8 bytes to 16-bit score rows of the same width.
template <int kBlocks>
inline void add_rows_u16(const uint8_t* row, int w, int side, uint16_t* out) {
  const __m128i zero = _mm_setzero_si128();
  for (int dy = 0; dy < side; ++dy, row += w, out += 8 * kBlocks) {
    for (int b = 0; b < kBlocks; ++b) {
      const __m128i v = _mm_unpacklo_epi8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(row + 8 * b)), zero);
      __m128i* o = reinterpret_cast<__m128i*>(out + 8 * b);
      _mm_storeu_si128(o, _mm_add_epi16(_mm_loadu_si128(o), v));
    }
  }
}

// accumulate_u32's sums, 8 offsets per SSE2 step in 16-bit lanes: each score row is padded to
// `stride` (a multiple of 8) and the padding columns (reading the field beyond the window) are
// dropped when the rows are added to `base`. Points whose padded window leaves the grid go the
// clipped scalar way. The same integer sums.
void accumulate_u16(const Eigen::Vector2i* cells, size_t num_cells, int n, const ProbabilityGrid& grid,
                    uint16_t* scratch, uint32_t* base) {
  const int side = 2 * n + 1, stride = (side + 7) & ~7;
  const uint8_t* values = grid.field().data();
  const int w = grid.width(), h = grid.height();
  std::fill(scratch, scratch + size_t(side) * stride, uint16_t(0));
  const __m128i zero = _mm_setzero_si128();
  for (size_t i = 0; i < num_cells; ++i) {
    const Eigen::Vector2i& c = cells[i];
    const bool inside = c.x() - n >= 0 && c.y() - n >= 0 && c.x() - n + stride <= w && c.y() + n < h;
    if (!inside) {
      const int k0 = std::max(0, n - c.x()), k1 = std::min(side, w - (c.x() - n));
      const int d0 = std::max(0, n - c.y()), d1 = std::min(side, h - (c.y() - n));
      for (int dy = d0; dy < d1; ++dy) {
        const uint8_t* row = values + size_t(c.y() - n + dy) * w + (c.x() - n);
        uint16_t* out = scratch + size_t(dy) * stride;
        for (int k = k0; k < k1; ++k) out[k] = uint16_t(out[k] + row[k]);
      }
      continue;
    }
    const uint8_t* row = values + size_t(c.y() - n) * w + (c.x() - n);
    switch (stride) {  // the common widths unrolled
      case 8:
        add_rows_u16<1>(row, w, side, scratch);
        break;
      case 16:
        add_rows_u16<2>(row, w, side, scratch);
        break;
      case 24:
        add_rows_u16<3>(row, w, side, scratch);
        break;
      case 32:
        add_rows_u16<4>(row, w, side, scratch);
        break;
      default: {
        uint16_t* out = scratch;
        for (int dy = 0; dy < side; ++dy, row += w, out += stride) {
          for (int k = 0; k < stride; k += 8) {
            const __m128i v = _mm_unpacklo_epi8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(row + k)), zero);
            __m128i* o = reinterpret_cast<__m128i*>(out + k);
            _mm_storeu_si128(o, _mm_add_epi16(_mm_loadu_si128(o), v));
          }
        }
      }
    }
  }
  for (int dy = 0; dy < side; ++dy) {
    const uint16_t* in = scratch + size_t(dy) * stride;
    uint32_t* out = base + size_t(dy) * side;
    for (int k = 0; k < side; ++k) out[k] += in[k];
  }
}
#endif

void accumulate(const std::vector<Eigen::Vector2i>& cells, int n, const ProbabilityGrid& grid,
                std::vector<uint16_t>* scratch, std::vector<uint32_t>* scores) {
#if defined(__SSE2__)
  const int side = 2 * n + 1, stride = (side + 7) & ~7;
  scratch->resize(size_t(side) * stride);
  for (size_t i = 0; i < cells.size(); i += kMaxPointsU16) {
    accumulate_u16(cells.data() + i, std::min(kMaxPointsU16, cells.size() - i), n, grid, scratch->data(),
                   scores->data());
  }
#else
  (void)scratch;
  accumulate_u32(cells.data(), cells.size(), n, grid, scores->data());
#endif
}

}  // namespace

CorrelativeScanMatcher::CorrelativeScanMatcher(const CorrelativeScanMatcherOptions& options) : options_(options) {}

Eigen::Matrix2d score_surface_covariance(const ProbabilityGrid& grid, const SE2& T,
                                         const std::vector<Eigen::Vector2f>& points,
                                         const ScoreSurfaceOptions& options) {
  const double res = grid.resolution_m();
  const int step = std::max(1, int(std::lround(options.step_m / res)));
  const int k = std::max(1, int(std::lround(options.window_m / (step * res))));
  if (points.empty() || grid.width() == 0) return Eigen::Matrix2d::Identity() * (k * step * res) * (k * step * res);
  std::vector<Eigen::Vector2i> cells;
  const size_t stride =
      options.max_points > 0 ? (points.size() + options.max_points - 1) / size_t(options.max_points) : 1;
  cells.reserve(points.size() / stride + 1);
  for (size_t i = 0; i < points.size(); i += stride) cells.push_back(grid.cell_of(T * points[i].cast<double>()));
  const int side = 2 * k + 1;
  std::vector<double> score(size_t(side) * side, 0.0);
  if (step == 1) {
    // Every offset of the window: the correlative search's row accumulation (the same integer sums).
    std::vector<uint32_t> sums(score.size(), 0u);
    std::vector<uint16_t> scratch;
    accumulate(cells, k, grid, &scratch, &sums);
    for (size_t i = 0; i < score.size(); ++i) score[i] = int(sums[i]) / (255.0 * double(cells.size()));
  } else {
    const uint8_t* field = grid.field().data();
    const int w = grid.width(), h = grid.height();
    for (int iy = 0; iy < side; ++iy) {
      for (int ix = 0; ix < side; ++ix) {
        const int dx = (ix - k) * step, dy = (iy - k) * step;
        int sum = 0;
        for (const auto& c : cells) {
          const unsigned col = unsigned(c.x() + dx), row = unsigned(c.y() + dy);
          if (col < unsigned(w) && row < unsigned(h)) sum += field[size_t(row) * w + col];
        }
        score[size_t(iy) * side + ix] = sum / (255.0 * double(cells.size()));
      }
    }
  }
  return covariance_of_score_lattice(score, k, step * res, options.temperature);
}

Eigen::Matrix2d covariance_of_score_lattice(const std::vector<double>& score, int k, double lattice_step_m,
                                            double temperature) {
  const int side = 2 * k + 1;
  const double best = *std::max_element(score.begin(), score.end());
  double s = 0.0;
  Eigen::Vector2d u = Eigen::Vector2d::Zero();
  Eigen::Matrix2d K = Eigen::Matrix2d::Zero();
  for (int iy = 0; iy < side; ++iy) {
    for (int ix = 0; ix < side; ++ix) {
      const double p = std::exp((score[size_t(iy) * side + ix] - best) / temperature);
      const Eigen::Vector2d d = lattice_step_m * Eigen::Vector2d(ix - k, iy - k);
      s += p;
      u += p * d;
      K += p * d * d.transpose();
    }
  }
  // The lattice cannot resolve less than its step: add the variance of a uniform step-wide cell.
  const double floor = lattice_step_m * lattice_step_m / 12.0;
  return K / s - (u / s) * (u / s).transpose() + Eigen::Matrix2d::Identity() * floor;
}

double CorrelativeScanMatcher::angular_step_rad(double range_m, double resolution_m) {
  range_m = std::max(range_m, 2.0 * resolution_m);
  // Law of cosines: the chord of a step at range r equals one cell (Cartographer, Olson).
  return std::acos(1.0 - (resolution_m * resolution_m) / (2.0 * range_m * range_m));
}

CorrelativeMatch CorrelativeScanMatcher::match(const SE2& initial, const std::vector<Eigen::Vector2f>& points,
                                               const ProbabilityGrid& grid, double linear_window_m,
                                               double angular_window_rad) const {
  CorrelativeMatch best;
  best.pose = initial;
  if (points.empty() || grid.width() == 0) return best;
  const double res = grid.resolution_m();
  const double range_m = std::min(max_range_m(points), options_.max_range_for_step_m);
  const double step_rad = angular_step_rad(range_m, res);
  const int num_angles = int(std::ceil(angular_window_rad / step_rad));
  const int n = int(std::ceil(linear_window_m / res));
  const int side = 2 * n + 1;
  std::vector<Eigen::Vector2i> cells(points.size());
  std::vector<uint32_t> scores(size_t(side) * side);
  std::vector<uint16_t> scratch;
  // Translation penalty per offset, computed once per search (not per angle).
  std::vector<float> trans_factor(size_t(side) * side);
  for (int dy = -n; dy <= n; ++dy) {
    for (int dx = -n; dx <= n; ++dx) {
      const double trans_cost = options_.translation_delta_cost_weight * res * std::hypot(double(dx), double(dy));
      trans_factor[size_t(dy + n) * side + dx + n] = float(std::exp(-trans_cost * trans_cost));
    }
  }
  const double norm = 1.0 / (255.0 * double(points.size()));
  const Eigen::Vector2d origin = grid.origin_m();
  const double inv_res = 1.0 / res;
  double best_weighted = -1.0;
  for (int a = -num_angles; a <= num_angles; ++a) {
    const double dyaw = a * step_rad;
    const Eigen::Matrix2d R = Eigen::Rotation2Dd(initial.yaw() + dyaw).toRotationMatrix();
    const Eigen::Vector2d t = (initial.translation() - origin) * inv_res;
    const Eigen::Matrix2d Rs = R * inv_res;
    for (size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector2d q = Rs * points[i].cast<double>() + t;
      cells[i] = Eigen::Vector2i(int(std::floor(q.x())), int(std::floor(q.y())));
    }
    std::fill(scores.begin(), scores.end(), 0u);
    accumulate(cells, n, grid, &scratch, &scores);
    const double rot_cost = options_.rotation_delta_cost_weight * dyaw;
    const float rot_factor = float(std::exp(-rot_cost * rot_cost));
    // Best of this angle by the weighted score (exact ties keep the first, as before).
    float best_here = -1.f;
    size_t best_index = 0;
    for (size_t k = 0; k < scores.size(); ++k) {
      const float weighted = float(scores[k]) * trans_factor[k];
      if (weighted > best_here) {
        best_here = weighted;
        best_index = k;
      }
    }
    best.candidates += int(scores.size());
    const double weighted = double(best_here) * rot_factor * norm;
    if (weighted > best_weighted) {
      best_weighted = weighted;
      const int dx = int(best_index % side) - n, dy = int(best_index / side) - n;
      best.score = double(scores[best_index]) * norm;
      best.pose = SE2(initial.translation() + res * Eigen::Vector2d(dx, dy), initial.yaw() + dyaw);
    }
  }
  return best;
}

}  // namespace cairn::agent
