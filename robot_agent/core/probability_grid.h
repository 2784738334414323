#pragma once
// Cartographer's ProbabilityGrid (Hess et al., "Real-Time Loop Closure in 2D LIDAR SLAM", ICRA 2016,
// Sec. III-B): each cell stores a 15-bit value, 0 = unknown, 1..32767 mapping linearly to an
// occupancy probability in [kMinProbability, kMaxProbability]. Scans update cells incrementally with
// precomputed odds-multiplication tables (range_data_inserter.h), so inserting a scan costs one table
// lookup per touched cell and no grid is ever rebuilt. The grid grows (doubling) to fit new scans.
// Rows grow with +y, columns with +x; cell (0,0) has its lower-left corner at origin_m().
// Beside the probabilities the grid keeps a likelihood field (Olson, "Real-Time Correlative Scan
// Matching", ICRA 2009, Sec. III-A): every hit splats a small Gaussian (max-composited, 0..255), so the
// correlative and branch-and-bound searches see a smooth score even where walls were hit only once,
// without rebuilding a blurred grid per scan.
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <vector>

#include "common/occupancy_grid.h"

namespace cairn::agent {

constexpr float kMinProbability = 0.1f;
constexpr float kMaxProbability = 0.9f;
constexpr uint16_t kUnknownValue = 0;
constexpr uint16_t kMaxValue = 32767;
constexpr uint16_t kUpdateMarker = 1u << 15;

/// value -> probability for 0..kMaxValue (entry 0, unknown, holds kMinProbability).
extern const float* const kValueToProbability;
/// Probability of a known value (1..kMaxValue); table lookup.
inline float value_to_probability(uint16_t value) { return kValueToProbability[value & kMaxValue]; }
/// Nearest value of a probability (clamped to [kMinProbability, kMaxProbability]); never 0.
uint16_t probability_to_value(float probability);

/// Allocates with calloc and leaves value-initialisation out: calloc knows when its memory is fresh
/// from the kernel (already zero) and skips the memset that std::vector's value-initialisation of a
/// new grid would always do. (Mapping every grid anonymously to keep unwritten pages lazy was
/// measured slower: page faults cost more than the memset in a paravirtualised VM.)
template <typename T>
struct ZeroedAllocator {
  using value_type = T;
  ZeroedAllocator() = default;
  template <typename U>
  ZeroedAllocator(const ZeroedAllocator<U>&) {}
  T* allocate(size_t n) {
    if (void* p = std::calloc(n, sizeof(T))) return static_cast<T*>(p);
    throw std::bad_alloc();
  }
  void deallocate(T* p, size_t) { std::free(p); }
  template <typename U>
  void construct(U*) {}  // memory is already zero
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
  template <typename U>
  bool operator==(const ZeroedAllocator<U>&) const {
    return true;
  }
  template <typename U>
  bool operator!=(const ZeroedAllocator<U>&) const {
    return false;
  }
};
template <typename T>
using ZeroedVector = std::vector<T, ZeroedAllocator<T>>;

class ProbabilityGrid {
 public:
  ProbabilityGrid() = default;
  /// `fill_probability`: what unknown cells (and cells outside) read as.
  ProbabilityGrid(const Eigen::Vector2d& origin_m, double resolution_m, int width, int height,
                  float fill_probability = kMinProbability);

  /// Probabilities of `grid`; unknown cells read as `unknown_probability`.
  static ProbabilityGrid from_occupancy(const OccupancyGrid& grid, float unknown_probability);

  /// The grid convolved with a separable Gaussian of `sigma_cells` (kernel radius 2 sigma).
  ProbabilityGrid blurred(double sigma_cells) const;

  int width() const { return width_; }
  int height() const { return height_; }
  double resolution_m() const { return resolution_m_; }
  const Eigen::Vector2d& origin_m() const { return origin_m_; }
  bool contains(int col, int row) const { return col >= 0 && row >= 0 && col < width_ && row < height_; }
  /// Probability of a cell; `outside` for cells out of bounds, fill_probability() when unknown.
  float at(int col, int row, float outside) const {
    return contains(col, row) ? probability_of(values_[size_t(row) * width_ + col]) : outside;
  }
  float probability_of(uint16_t value) const {
    return value == kUnknownValue ? fill_probability_ : kValueToProbability[value];
  }
  void set_probability(int col, int row, float p) {
    values_[size_t(row) * width_ + col] = probability_to_value(p);
    include_written_cell(col, row);
  }
  bool known(int col, int row) const { return contains(col, row) && values_[size_t(row) * width_ + col] != 0; }
  Eigen::Vector2i cell_of(const Eigen::Vector2d& p_m) const {
    const Eigen::Vector2d c = (p_m - origin_m_) / resolution_m_;
    return {int(std::floor(c.x())), int(std::floor(c.y()))};
  }
  /// Continuous cell coordinates (col, row) where integer values are cell centres.
  Eigen::Vector2d continuous_cell(const Eigen::Vector2d& p_m) const {
    return (p_m - origin_m_) / resolution_m_ - Eigen::Vector2d(0.5, 0.5);
  }
  Eigen::Vector2d cell_center_m(int col, int row) const {
    return origin_m_ + resolution_m_ * Eigen::Vector2d(col + 0.5, row + 0.5);
  }
  float fill_probability() const { return fill_probability_; }

  /// Grows (only the axes that overflow, at least doubling them, slack on the overflowing side,
  /// keeping cell alignment) so the box [min_m, max_m] is inside.
  void grow_to_include(const Eigen::Vector2d& min_m, const Eigen::Vector2d& max_m);
  /// Shrinks to the bounding box of known cells (plus `margin_cells`), e.g. when a submap is finished.
  void crop_to_known(int margin_cells = 2);

  const ZeroedVector<uint16_t>& values() const { return values_; }
  /// Raw cell access for bulk writers (the range data inserter): cells written must lie inside a
  /// box declared with include_written_box, or crop_to_known / growth may drop them.
  ZeroedVector<uint16_t>& mutable_values() { return values_; }
  /// Declares that cells (and field values) inside [min_m, max_m] may be written (clamped to the grid).
  void include_written_box(const Eigen::Vector2d& min_m, const Eigen::Vector2d& max_m);
  /// Cell box that can hold known cells or field values: [min, max] (empty when max < min).
  const Eigen::Vector2i& written_min() const { return written_min_; }
  const Eigen::Vector2i& written_max() const { return written_max_; }
  /// Likelihood field, 0..255, same layout as values().
  const ZeroedVector<uint8_t>& field() const { return field_; }
  float field_at(int col, int row) const {
    return contains(col, row) ? field_[size_t(row) * width_ + col] * (1.f / 255.f) : 0.f;
  }
  /// Max-composites the hit kernel (Gaussian of `sigma_cells`, radius 2 sigma) centred on a cell.
  void splat_hit(int col, int row, double sigma_cells = 1.0);
  /// Recomputes the field from cells more likely occupied than not (after bulk edits).
  void rebuild_field(double sigma_cells = 1.0);

 private:
  Eigen::Vector2d origin_m_ = Eigen::Vector2d::Zero();
  double resolution_m_ = 0.05;
  int width_ = 0;
  int height_ = 0;
  float fill_probability_ = kMinProbability;
  void include_written_cell(int col, int row) {
    written_min_ = written_min_.cwiseMin(Eigen::Vector2i(col, row));
    written_max_ = written_max_.cwiseMax(Eigen::Vector2i(col, row));
  }
  ZeroedVector<uint16_t> values_;
  ZeroedVector<uint8_t> field_;
  Eigen::Vector2i written_min_{INT32_MAX, INT32_MAX}, written_max_{-1, -1};
  double kernel_sigma_cells_ = -1.0;
  std::vector<uint8_t> kernel_;        ///< splat_hit's Gaussian, row-major over [-radius, radius]^2
  std::vector<uint8_t> kernel_rows8_;  ///< the same, each row zero-padded to 8 bytes (SSE2 path)
};

}  // namespace cairn::agent
