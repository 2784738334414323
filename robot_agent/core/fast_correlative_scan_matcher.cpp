#include "robot_agent/core/fast_correlative_scan_matcher.h"

#include <algorithm>
#include <cmath>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "robot_agent/core/correlative_scan_matcher.h"

namespace cairn::agent {
namespace {

// out[k] = max(a[k], b[k]) for k < n (SSE2: 16 cells per step).
inline void max_row(const uint8_t* a, const uint8_t* b, uint8_t* out, int n) {
  int k = 0;
#if defined(__SSE2__)
  for (; k + 16 <= n; k += 16) {
    const __m128i va = _mm_loadu_si128(reinterpret_cast<const __m128i*>(a + k));
    const __m128i vb = _mm_loadu_si128(reinterpret_cast<const __m128i*>(b + k));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + k), _mm_max_epu8(va, vb));
  }
#endif
  for (; k < n; ++k) out[k] = std::max(a[k], b[k]);
}

}  // namespace

void PrecomputationGrid::allocate(int width, int height) {
  width_ = width;
  height_ = height;
  num_cells_ = size_t(width) * size_t(height);
  cells_.reset(new uint8_t[num_cells_]);  // default-initialised: no memset, filled by the caller
}

PrecomputationGrid PrecomputationGrid::from_grid(const ProbabilityGrid& grid) {
  // Only cells near hits have a non-zero field: crop to their bounding box (a finished submap's
  // free-space rays reach far beyond its walls).
  const auto& field = grid.field();
  int x0 = grid.width(), y0 = grid.height(), x1 = -1, y1 = -1;
  const int c0 = std::max(0, grid.written_min().x()), c1 = std::min(grid.width() - 1, grid.written_max().x());
  for (int r = std::max(0, grid.written_min().y()); r <= std::min(grid.height() - 1, grid.written_max().y()); ++r) {
    const uint8_t* row = field.data() + size_t(r) * grid.width();
    int first = -1, last = -1;
    for (int c = c0; c <= c1; ++c) {
      if (row[c]) {
        first = c;
        break;
      }
    }
    if (first < 0) continue;
    for (int c = c1; c >= first; --c) {
      if (row[c]) {
        last = c;
        break;
      }
    }
    x0 = std::min(x0, first);
    x1 = std::max(x1, last);
    y0 = std::min(y0, r);
    y1 = r;
  }
  PrecomputationGrid g;
  if (x1 < 0) return g;
  g.x0_ = x0;
  g.y0_ = y0;
  g.allocate(x1 - x0 + 1, y1 - y0 + 1);
  for (int r = 0; r < g.height_; ++r) {
    std::copy_n(field.data() + size_t(r + y0) * grid.width() + x0, g.width_, g.cells_.get() + size_t(r) * g.width_);
  }
  return g;
}

PrecomputationGrid PrecomputationGrid::from_previous(const PrecomputationGrid& prev) {
  // max over a 2b block = max of the four b-blocks at (0,0), (b,0), (0,b), (b,b). A block starting
  // at col is non-zero only if it overlaps the previous level's extent: col in [x0 - b, x0 + w).
  PrecomputationGrid g;
  const int half = prev.block_;
  g.block_ = 2 * half;
  if (prev.width_ == 0) return g;
  g.x0_ = prev.x0_ - half;
  g.y0_ = prev.y0_ - half;
  g.allocate(prev.width_ + half, prev.height_ + half);
  // Separable: horizontal max of the two b-blocks (previous rows), then vertical max of that.
  // New column c <-> previous columns c - half and c (previous index space: col - prev.x0_), with
  // in[] zero outside [0, prev.width_): c < half reads in[c] only, c >= prev.width_ in[c - half] only.
  const int w = g.width_, pw = prev.width_;
  std::unique_ptr<uint8_t[]> horizontal(new uint8_t[size_t(w) * prev.height_]);
  for (int pr = 0; pr < prev.height_; ++pr) {
    const uint8_t* in = prev.cells_.get() + size_t(pr) * pw;
    uint8_t* out = horizontal.get() + size_t(pr) * w;
    const int lo = std::min(half, pw);  // [0, lo): in[c]; [lo, half): 0
    std::copy_n(in, lo, out);
    std::fill(out + lo, out + half, uint8_t(0));
    if (pw > half) max_row(in, in + half, out + half, pw - half);  // [half, pw): both
    const int tail0 = std::max(half, pw);                          // [tail0, w): in[c - half]
    std::copy_n(in + (tail0 - half), w - tail0, out + tail0);
  }
  for (int r = 0; r < g.height_; ++r) {
    uint8_t* out = g.cells_.get() + size_t(r) * w;
    const int ra = r - half, rb = r;  // previous rows
    const uint8_t* a = (ra >= 0 && ra < prev.height_) ? horizontal.get() + size_t(ra) * w : nullptr;
    const uint8_t* b = rb < prev.height_ ? horizontal.get() + size_t(rb) * w : nullptr;
    if (a && b) {
      max_row(a, b, out, w);
    } else if (a || b) {
      std::copy_n(a ? a : b, w, out);
    } else {
      std::fill(out, out + w, uint8_t(0));
    }
  }
  return g;
}

FastCorrelativeScanMatcher::FastCorrelativeScanMatcher(const ProbabilityGrid& grid,
                                                       const FastCorrelativeScanMatcherOptions& options)
    : options_(options), origin_m_(grid.origin_m()), resolution_m_(grid.resolution_m()) {
  // Only level 0 now; coarser levels when a search window first needs them (match()).
  levels_.push_back(PrecomputationGrid::from_grid(grid));
}

void FastCorrelativeScanMatcher::ensure_levels(int count) const {
  while (int(levels_.size()) < count) levels_.push_back(PrecomputationGrid::from_previous(levels_.back()));
}

size_t FastCorrelativeScanMatcher::memory_bytes() const {
  size_t n = 0;
  for (const auto& l : levels_) n += l.bytes();
  return n;
}

int FastCorrelativeScanMatcher::score(const DiscreteScan& scan, int level, int dx, int dy) const {
  const PrecomputationGrid& g = levels_[size_t(level)];
  if (!scan.cells.empty() && g.contains_box(scan.lo, scan.hi, dx, dy)) return g.sum_inside(scan.cells, dx, dy);
  return g.sum(scan.cells, dx, dy);
}

std::optional<FastCorrelativeScanMatcher::Candidate> FastCorrelativeScanMatcher::search(
    const std::vector<DiscreteScan>& scans, Candidate* candidates, size_t num_candidates, int level, int max_offset,
    int min_score, int* budget) const {
  *budget -= int(num_candidates);
  if (*budget < 0) return std::nullopt;
  Candidate* const end = candidates + num_candidates;
  for (Candidate* c = candidates; c != end; ++c) c->score = score(scans[c->angle], level, c->dx, c->dy);
  std::sort(candidates, end, [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
  std::optional<Candidate> best;
  for (const Candidate* it = candidates; it != end; ++it) {
    const Candidate& c = *it;
    if (c.score < min_score) break;  // sorted: no remaining bound can beat the best
    if (level == 0) {
      best = c;
      min_score = c.score + 1;
      continue;
    }
    const int half = 1 << (level - 1);
    Candidate children[4];  // on the stack: no allocation per branch
    size_t num_children = 0;
    for (int oy : {0, half}) {
      for (int ox : {0, half}) {
        if (c.dx + ox > max_offset || c.dy + oy > max_offset) continue;
        children[num_children++] = {c.angle, c.dx + ox, c.dy + oy, 0};
      }
    }
    if (*budget < 0) return std::nullopt;
    if (auto found = search(scans, children, num_children, level - 1, max_offset, min_score, budget)) {
      best = found;
      min_score = found->score + 1;
    }
  }
  return best;
}

std::optional<FastMatch> FastCorrelativeScanMatcher::match(const SE2& initial,
                                                           const std::vector<Eigen::Vector2f>& points,
                                                           double linear_window_m, double angular_window_rad,
                                                           double min_score, int* scored_candidates) const {
  if (points.empty()) return std::nullopt;
  double range_m = 0.0;
  for (const auto& p : points) range_m = std::max(range_m, double(p.norm()));
  const double step =
      CorrelativeScanMatcher::angular_step_rad(std::min(range_m, options_.max_range_for_step_m), resolution_m_);
  const int num_angles = int(std::ceil(angular_window_rad / step));
  std::vector<DiscreteScan> scans(2 * num_angles + 1);
  for (int a = -num_angles; a <= num_angles; ++a) {
    const Eigen::Matrix2d R = Eigen::Rotation2Dd(initial.yaw() + a * step).toRotationMatrix();
    DiscreteScan& scan = scans[size_t(a + num_angles)];
    auto& cells = scan.cells;
    cells.reserve(points.size());
    for (const auto& p : points) {
      const Eigen::Vector2d q = (R * p.cast<double>() + initial.translation() - origin_m_) / resolution_m_;
      cells.emplace_back(int(std::floor(q.x())), int(std::floor(q.y())));
    }
    scan.lo = scan.hi = cells.front();
    for (const auto& c : cells) {
      scan.lo = scan.lo.cwiseMin(c);
      scan.hi = scan.hi.cwiseMax(c);
    }
  }
  const int n = int(std::ceil(linear_window_m / resolution_m_));
  // Start at the coarsest level whose block still fits the window: coarser blocks only loosen bounds.
  const int depth = std::max(1, options_.branch_and_bound_depth);
  int top = 0;
  while (top + 1 < depth && (1 << top) < 2 * n + 1) ++top;
  ensure_levels(top + 1);
  const int step_cells = 1 << top;
  std::vector<Candidate> candidates;
  for (int a = 0; a < int(scans.size()); ++a) {
    for (int dy = -n; dy <= n; dy += step_cells) {
      for (int dx = -n; dx <= n; dx += step_cells) candidates.push_back({a, dx, dy, 0});
    }
  }
  const int min_sum = int(std::ceil(std::max(0.0, min_score) * 255.0 * double(points.size())));
  int budget = options_.max_scored_candidates;
  const auto best = search(scans, candidates.data(), candidates.size(), top, n, min_sum, &budget);
  if (scored_candidates) *scored_candidates = options_.max_scored_candidates - budget;
  if (!best || budget < 0) return std::nullopt;
  FastMatch out;
  out.pose = SE2(initial.translation() + resolution_m_ * Eigen::Vector2d(best->dx, best->dy),
                 initial.yaw() + (best->angle - num_angles) * step);
  out.score = best->score / (255.0 * double(points.size()));
  return out;
}

}  // namespace cairn::agent
