#include "robot_agent/core/probability_grid.h"

#include <algorithm>
#include <cmath>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace cairn::agent {
namespace {

std::vector<float> make_value_table() {
  std::vector<float> table(kMaxValue + 1, kMinProbability);
  for (int v = 1; v <= kMaxValue; ++v) {
    table[v] = kMinProbability + (kMaxProbability - kMinProbability) * float(v - 1) / float(kMaxValue - 1);
  }
  return table;
}

}  // namespace

const float* const kValueToProbability = []() {
  static const std::vector<float> table = make_value_table();
  return table.data();
}();

uint16_t probability_to_value(float p) {
  p = std::clamp(p, kMinProbability, kMaxProbability);
  return uint16_t(1 + std::lround((p - kMinProbability) / (kMaxProbability - kMinProbability) * (kMaxValue - 1)));
}

ProbabilityGrid::ProbabilityGrid(const Eigen::Vector2d& origin_m, double resolution_m, int width, int height,
                                 float fill_probability)
    : origin_m_(origin_m),
      resolution_m_(resolution_m),
      width_(std::max(0, width)),
      height_(std::max(0, height)),
      fill_probability_(fill_probability),
      values_(size_t(width_) * size_t(height_)),  // kUnknownValue == 0: lazily zeroed pages
      field_(values_.size()) {}

void ProbabilityGrid::include_written_box(const Eigen::Vector2d& min_m, const Eigen::Vector2d& max_m) {
  if (width_ == 0 || height_ == 0) return;
  const Eigen::Vector2i lo = cell_of(min_m).cwiseMax(Eigen::Vector2i(0, 0));
  const Eigen::Vector2i hi = cell_of(max_m).cwiseMin(Eigen::Vector2i(width_ - 1, height_ - 1));
  if (lo.x() > hi.x() || lo.y() > hi.y()) return;
  written_min_ = written_min_.cwiseMin(lo);
  written_max_ = written_max_.cwiseMax(hi);
}

void ProbabilityGrid::splat_hit(int col, int row, double sigma_cells) {
  const int radius = std::max(1, int(std::ceil(2.0 * sigma_cells)));
  if (sigma_cells != kernel_sigma_cells_) {  // the kernel is computed once per sigma
    kernel_sigma_cells_ = sigma_cells;
    kernel_.clear();
    kernel_rows8_.clear();
    for (int dy = -radius; dy <= radius; ++dy) {
      for (int dx = -radius; dx <= radius; ++dx) {
        kernel_.push_back(
            uint8_t(std::lround(255.0 * std::exp(-0.5 * (dx * dx + dy * dy) / (sigma_cells * sigma_cells)))));
      }
    }
  }
  const bool inside = col - radius >= 0 && row - radius >= 0 && col + radius < width_ && row + radius < height_;
  written_min_ = written_min_.cwiseMin(Eigen::Vector2i(std::max(0, col - radius), std::max(0, row - radius)));
  written_max_ =
      written_max_.cwiseMax(Eigen::Vector2i(std::min(width_ - 1, col + radius), std::min(height_ - 1, row + radius)));
#if defined(__SSE2__)
  // Kernel rows up to 8 wide: one 8-byte max per row, the kernel padded with zeros (max(f, 0) = f
  // leaves the cells beyond the kernel as they were; they must lie inside the row).
  if (inside && radius <= 3 && col - radius + 8 <= width_) {
    const int side = 2 * radius + 1;
    if (kernel_rows8_.size() != size_t(side) * 8) {
      kernel_rows8_.assign(size_t(side) * 8, 0);
      for (int r = 0; r < side; ++r) std::copy_n(&kernel_[size_t(r) * side], side, &kernel_rows8_[size_t(r) * 8]);
    }
    uint8_t* f = field_.data() + size_t(row - radius) * width_ + (col - radius);
    for (int r = 0; r < side; ++r, f += width_) {
      const __m128i v = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(f));
      const __m128i k8 = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(&kernel_rows8_[size_t(r) * 8]));
      _mm_storel_epi64(reinterpret_cast<__m128i*>(f), _mm_max_epu8(v, k8));
    }
    return;
  }
#endif
  const uint8_t* k = kernel_.data();
  for (int dy = -radius; dy <= radius; ++dy) {
    for (int dx = -radius; dx <= radius; ++dx, ++k) {
      if (!inside && !contains(col + dx, row + dy)) continue;
      uint8_t& f = field_[size_t(row + dy) * width_ + col + dx];
      f = std::max(f, *k);
    }
  }
}

void ProbabilityGrid::rebuild_field(double sigma_cells) {
  if (written_max_.x() < written_min_.x()) return;  // nothing written
  const Eigen::Vector2i lo = written_min_, hi = written_max_;
  for (int r = lo.y(); r <= hi.y(); ++r) std::fill_n(&field_[size_t(r) * width_ + lo.x()], hi.x() - lo.x() + 1, 0);
  for (int r = lo.y(); r <= hi.y(); ++r) {
    for (int c = lo.x(); c <= hi.x(); ++c) {
      const uint16_t v = values_[size_t(r) * width_ + c];
      if (v != kUnknownValue && value_to_probability(v) > 0.5f) splat_hit(c, r, sigma_cells);
    }
  }
}

ProbabilityGrid ProbabilityGrid::from_occupancy(const OccupancyGrid& grid, float unknown_probability) {
  ProbabilityGrid out(grid.origin_m(), grid.resolution_m(), grid.width(), grid.height(), unknown_probability);
  for (int r = 0; r < grid.height(); ++r) {
    for (int c = 0; c < grid.width(); ++c) {
      const float l = grid.log_odds(c, r);
      if (l != 0.f) out.set_probability(c, r, 1.f - 1.f / (1.f + std::exp(l)));
    }
  }
  out.rebuild_field();
  return out;
}

void ProbabilityGrid::grow_to_include(const Eigen::Vector2d& min_m, const Eigen::Vector2d& max_m) {
  const Eigen::Vector2i lo = cell_of(min_m), hi = cell_of(max_m);
  if (width_ > 0 && lo.x() >= 0 && lo.y() >= 0 && hi.x() < width_ && hi.y() < height_) return;
  // New extent: the union, grown only along the axes that need it, with a slack of the old size
  // (doubling, so repeated growth is amortised) on the side(s) that overflowed.
  auto extent = [](int lo, int hi, int size, int* new_size, int* shift) {
    if (size > 0 && lo >= 0 && hi < size) {
      *new_size = size;
      *shift = 0;
      return;
    }
    const int x0 = std::min(0, lo), x1 = std::max(size - 1, hi);
    const int need = x1 - x0 + 1;
    const int slack = std::max(8, size);
    const bool low = lo < 0, high = hi >= size;
    const int pad_low = low ? (high ? slack / 2 : slack) : 0;
    const int pad_high = high ? (low ? slack - slack / 2 : slack) : 0;
    *new_size = need + pad_low + pad_high;
    *shift = -x0 + pad_low;  // old cell c -> c + shift
  };
  int new_w = 0, new_h = 0, shift_x = 0, shift_y = 0;
  extent(lo.x(), hi.x(), width_, &new_w, &shift_x);
  extent(lo.y(), hi.y(), height_, &new_h, &shift_y);
  ZeroedVector<uint16_t> cells(size_t(new_w) * size_t(new_h));
  ZeroedVector<uint8_t> field(cells.size());
  // Only the written box holds data; the rest stays untouched (lazily zeroed) memory.
  if (written_max_.x() >= written_min_.x()) {
    const int x0 = written_min_.x(), n = written_max_.x() - x0 + 1;
    for (int r = written_min_.y(); r <= written_max_.y(); ++r) {
      std::copy_n(&values_[size_t(r) * width_ + x0], n, &cells[size_t(r + shift_y) * new_w + x0 + shift_x]);
      std::copy_n(&field_[size_t(r) * width_ + x0], n, &field[size_t(r + shift_y) * new_w + x0 + shift_x]);
    }
    written_min_ += Eigen::Vector2i(shift_x, shift_y);
    written_max_ += Eigen::Vector2i(shift_x, shift_y);
  }
  values_.swap(cells);
  field_.swap(field);
  origin_m_ -= resolution_m_ * Eigen::Vector2d(shift_x, shift_y);
  width_ = new_w;
  height_ = new_h;
}

void ProbabilityGrid::crop_to_known(int margin_cells) {
  int x0 = width_, y0 = height_, x1 = -1, y1 = -1;
  for (int r = std::max(0, written_min_.y()); r <= std::min(height_ - 1, written_max_.y()); ++r) {
    for (int c = std::max(0, written_min_.x()); c <= std::min(width_ - 1, written_max_.x()); ++c) {
      if (values_[size_t(r) * width_ + c] == kUnknownValue) continue;
      x0 = std::min(x0, c);
      x1 = std::max(x1, c);
      y0 = std::min(y0, r);
      y1 = std::max(y1, r);
    }
  }
  if (x1 < 0) return;
  x0 = std::max(0, x0 - margin_cells);
  y0 = std::max(0, y0 - margin_cells);
  x1 = std::min(width_ - 1, x1 + margin_cells);
  y1 = std::min(height_ - 1, y1 + margin_cells);
  const int w = x1 - x0 + 1, h = y1 - y0 + 1;
  ZeroedVector<uint16_t> cells(size_t(w) * size_t(h));
  ZeroedVector<uint8_t> field(cells.size());
  for (int r = 0; r < h; ++r) {
    std::copy_n(&values_[size_t(r + y0) * width_ + x0], w, &cells[size_t(r) * w]);
    std::copy_n(&field_[size_t(r + y0) * width_ + x0], w, &field[size_t(r) * w]);
  }
  values_.swap(cells);
  field_.swap(field);
  origin_m_ += resolution_m_ * Eigen::Vector2d(x0, y0);
  width_ = w;
  height_ = h;
  written_min_ = Eigen::Vector2i(0, 0);
  written_max_ = Eigen::Vector2i(w - 1, h - 1);
}

ProbabilityGrid ProbabilityGrid::blurred(double sigma_cells) const {
  if (sigma_cells <= 0.0 || values_.empty()) return *this;
  const int radius = std::max(1, int(std::ceil(2.0 * sigma_cells)));
  std::vector<float> kernel(2 * radius + 1);
  float sum = 0.f;
  for (int k = -radius; k <= radius; ++k) {
    kernel[k + radius] = float(std::exp(-0.5 * k * k / (sigma_cells * sigma_cells)));
    sum += kernel[k + radius];
  }
  for (float& k : kernel) k /= sum;
  std::vector<float> tmp(values_.size());
  for (int r = 0; r < height_; ++r) {
    for (int c = 0; c < width_; ++c) {
      float acc = 0.f;
      for (int k = -radius; k <= radius; ++k) acc += kernel[k + radius] * at(c + k, r, fill_probability_);
      tmp[size_t(r) * width_ + c] = acc;
    }
  }
  ProbabilityGrid out = *this;
  for (int r = 0; r < height_; ++r) {
    for (int c = 0; c < width_; ++c) {
      float acc = 0.f;
      for (int k = -radius; k <= radius; ++k) {
        const int rr = r + k;
        acc += kernel[k + radius] * (rr >= 0 && rr < height_ ? tmp[size_t(rr) * width_ + c] : fill_probability_);
      }
      out.set_probability(c, r, acc);
    }
  }
  out.rebuild_field();
  return out;
}

}  // namespace cairn::agent
