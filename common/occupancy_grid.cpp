#include "common/occupancy_grid.h"

#include <algorithm>
#include <cmath>
#include <fstream>

namespace cairn {

OccupancyGrid::OccupancyGrid(const OccupancyGridOptions& options) : options_(options) {}

OccupancyGrid::OccupancyGrid(const OccupancyGridOptions& options, const Eigen::Vector2d& min_m,
                             const Eigen::Vector2d& max_m)
    : options_(options) {
  ensure_contains(min_m, max_m);
}

Eigen::Vector2i OccupancyGrid::cell_of(const Eigen::Vector2d& p_m) const {
  const Eigen::Vector2d c = (p_m - origin_m_) / options_.resolution_m;
  return {int(std::floor(c.x())), int(std::floor(c.y()))};
}

Eigen::Vector2d OccupancyGrid::cell_center_m(int col, int row) const {
  return origin_m_ + options_.resolution_m * Eigen::Vector2d(col + 0.5, row + 0.5);
}

float OccupancyGrid::log_odds(int col, int row) const {
  return contains(col, row) ? cells_[size_t(row) * width_ + col] : 0.f;
}

double OccupancyGrid::probability(int col, int row) const {
  return 1.0 - 1.0 / (1.0 + std::exp(double(log_odds(col, row))));
}

void OccupancyGrid::ensure_contains(const Eigen::Vector2d& min_m, const Eigen::Vector2d& max_m) {
  const double res = options_.resolution_m;
  if (width_ == 0) {
    // Snap the origin to the resolution so grids of the same resolution align.
    origin_m_ = (min_m / res).array().floor().matrix() * res;
    width_ = std::max(1, int(std::ceil((max_m.x() - origin_m_.x()) / res)) + 1);
    height_ = std::max(1, int(std::ceil((max_m.y() - origin_m_.y()) / res)) + 1);
    cells_.assign(size_t(width_) * height_, 0.f);
    return;
  }
  const Eigen::Vector2i lo = cell_of(min_m), hi = cell_of(max_m);
  if (lo.x() >= 0 && lo.y() >= 0 && hi.x() < width_ && hi.y() < height_) return;
  // Grow with a margin so repeated small growth stays amortised.
  const int margin = int(std::ceil(5.0 / res));
  const int add_left = lo.x() < 0 ? -lo.x() + margin : 0;
  const int add_bottom = lo.y() < 0 ? -lo.y() + margin : 0;
  const int add_right = hi.x() >= width_ ? hi.x() - width_ + 1 + margin : 0;
  const int add_top = hi.y() >= height_ ? hi.y() - height_ + 1 + margin : 0;
  const int new_w = width_ + add_left + add_right, new_h = height_ + add_bottom + add_top;
  std::vector<float> grown(size_t(new_w) * new_h, 0.f);
  for (int r = 0; r < height_; ++r) {
    std::copy_n(&cells_[size_t(r) * width_], width_, &grown[size_t(r + add_bottom) * new_w + add_left]);
  }
  cells_.swap(grown);
  width_ = new_w;
  height_ = new_h;
  origin_m_ -= res * Eigen::Vector2d(add_left, add_bottom);
}

void OccupancyGrid::update_cell(int col, int row, float delta) {
  if (!contains(col, row)) {
    const Eigen::Vector2d p = cell_center_m(col, row);
    ensure_contains(p, p);
    const Eigen::Vector2i c = cell_of(p);
    col = c.x();
    row = c.y();
  }
  if (col < clip_lo_.x() || row < clip_lo_.y() || col >= clip_hi_.x() || row >= clip_hi_.y()) return;
  float& v = at(col, row);
  v = std::clamp(v + delta, options_.min_log_odds, options_.max_log_odds);
  if (v == 0.f) v = delta > 0 ? 1e-6f : -1e-6f;  // stays "known"
}

namespace {

/// Bresenham line from `from` to `to`, the end cell excluded: visit(col, row) for each cell until it
/// returns false. Returns whether every cell was visited.
template <typename Visit>
bool walk_line(const Eigen::Vector2i& from, const Eigen::Vector2i& to, Visit visit) {
  int x0 = from.x(), y0 = from.y();
  const int x1 = to.x(), y1 = to.y();
  const int dx = std::abs(x1 - x0), dy = -std::abs(y1 - y0);
  const int sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1;
  int err = dx + dy;
  while (!(x0 == x1 && y0 == y1)) {
    if (!visit(x0, y0)) return false;
    const int e2 = 2 * err;
    if (e2 >= dy) {
      err += dy;
      x0 += sx;
    }
    if (e2 <= dx) {
      err += dx;
      y0 += sy;
    }
  }
  return true;
}

}  // namespace

void OccupancyGrid::trace_ray(const Eigen::Vector2i& from, const Eigen::Vector2i& to, bool hit_at_end) {
  // The cells up to the end get a miss; the end cell a hit (or a miss when no return).
  walk_line(from, to, [this](int col, int row) {
    update_cell(col, row, options_.miss_log_odds);
    return true;
  });
  update_cell(to.x(), to.y(), hit_at_end ? options_.hit_log_odds : options_.miss_log_odds);
}

bool OccupancyGrid::line_clear(const Eigen::Vector2d& a_m, const Eigen::Vector2d& b_m, double occupied_above) const {
  const Eigen::Vector2i b = cell_of(b_m);
  const auto free = [&](int col, int row) { return !contains(col, row) || probability(col, row) <= occupied_above; };
  return walk_line(cell_of(a_m), b, free) && free(b.x(), b.y());
}

void OccupancyGrid::insert_scan(const SE2& T_map_sensor, const std::vector<Eigen::Vector2f>& points,
                                const std::vector<Eigen::Vector2f>& no_return_points) {
  insert_scan_impl(T_map_sensor, points, no_return_points, nullptr, nullptr);
}

void OccupancyGrid::insert_scan_clipped(const SE2& T_map_sensor, const std::vector<Eigen::Vector2f>& points,
                                        const std::vector<Eigen::Vector2f>& no_return_points,
                                        const Eigen::Vector2d& clip_min_m, const Eigen::Vector2d& clip_max_m) {
  insert_scan_impl(T_map_sensor, points, no_return_points, &clip_min_m, &clip_max_m);
}

void OccupancyGrid::cell_range(const Eigen::Vector2d& min_m, const Eigen::Vector2d& max_m, Eigen::Vector2i* lo,
                               Eigen::Vector2i* hi) const {
  // Cell c's centre origin + (c + 0.5) res lies in [min, max) iff c in [ceil(a - 0.5), ceil(b - 0.5)).
  const Eigen::Vector2d a = (min_m - origin_m_) / options_.resolution_m,
                        b = (max_m - origin_m_) / options_.resolution_m;
  *lo = Eigen::Vector2i(int(std::ceil(a.x() - 0.5)), int(std::ceil(a.y() - 0.5))).cwiseMax(Eigen::Vector2i(0, 0));
  *hi = Eigen::Vector2i(int(std::ceil(b.x() - 0.5)), int(std::ceil(b.y() - 0.5)))
            .cwiseMin(Eigen::Vector2i(width_, height_));
}

void OccupancyGrid::clear_region(const Eigen::Vector2d& min_m, const Eigen::Vector2d& max_m) {
  Eigen::Vector2i lo, hi;
  cell_range(min_m, max_m, &lo, &hi);
  for (int r = lo.y(); r < hi.y(); ++r) {
    for (int c = lo.x(); c < hi.x(); ++c) at(c, r) = 0.f;
  }
}

void OccupancyGrid::insert_scan_impl(const SE2& T_map_sensor, const std::vector<Eigen::Vector2f>& points,
                                     const std::vector<Eigen::Vector2f>& no_return_points,
                                     const Eigen::Vector2d* clip_min_m, const Eigen::Vector2d* clip_max_m) {
  const double max_r = options_.max_range_m;
  auto clip = [&](const Eigen::Vector2f& p, bool* clipped) {
    Eigen::Vector2d q = p.cast<double>();
    const double r = q.norm();
    *clipped = r > max_r;
    if (*clipped) q *= max_r / r;
    return Eigen::Vector2d(T_map_sensor * q);
  };
  // Grow once for the whole scan.
  Eigen::Vector2d lo = T_map_sensor.translation(), hi = lo;
  std::vector<std::pair<Eigen::Vector2d, bool>> ends;
  ends.reserve(points.size() + no_return_points.size());
  for (const auto& p : points) {
    bool clipped = false;
    ends.emplace_back(clip(p, &clipped), !clipped);
  }
  for (const auto& p : no_return_points) {
    bool clipped = false;
    ends.emplace_back(clip(p, &clipped), false);
  }
  for (const auto& e : ends) {
    lo = lo.cwiseMin(e.first);
    hi = hi.cwiseMax(e.first);
  }
  ensure_contains(lo, hi);
  if (clip_min_m) {  // after growing: cell indices are final
    cell_range(*clip_min_m, *clip_max_m, &clip_lo_, &clip_hi_);
    if (clip_lo_.x() >= clip_hi_.x() || clip_lo_.y() >= clip_hi_.y()) {
      clip_lo_ = {INT32_MIN, INT32_MIN};
      clip_hi_ = {INT32_MAX, INT32_MAX};
      return;  // nothing of the clip box lies in the grid
    }
  }
  const Eigen::Vector2i origin_cell = cell_of(T_map_sensor.translation());
  for (const auto& e : ends) trace_ray(origin_cell, cell_of(e.first), e.second);
  clip_lo_ = {INT32_MIN, INT32_MIN};
  clip_hi_ = {INT32_MAX, INT32_MAX};
}

double OccupancyGrid::known_area_m2() const {
  const size_t n = std::count_if(cells_.begin(), cells_.end(), [](float v) { return v != 0.f; });
  return double(n) * options_.resolution_m * options_.resolution_m;
}

std::vector<uint8_t> OccupancyGrid::to_image(double occupied_threshold, double free_threshold) const {
  std::vector<uint8_t> img(size_t(width_) * height_, 205);
  for (int r = 0; r < height_; ++r) {
    for (int c = 0; c < width_; ++c) {
      if (!known(c, r)) continue;
      const double p = probability(c, r);
      uint8_t v = 205;
      if (p >= occupied_threshold)
        v = 0;
      else if (p <= free_threshold)
        v = 254;
      img[size_t(height_ - 1 - r) * width_ + c] = v;  // top row first
    }
  }
  return img;
}

bool OccupancyGrid::write_pgm_yaml(const std::string& stem) const {
  const std::vector<uint8_t> img = to_image();
  {
    std::ofstream pgm(stem + ".pgm", std::ios::binary);
    if (!pgm) return false;
    pgm << "P5\n# cairn occupancy grid\n" << width_ << " " << height_ << "\n255\n";
    pgm.write(reinterpret_cast<const char*>(img.data()), std::streamsize(img.size()));
    if (!pgm) return false;
  }
  std::ofstream yaml(stem + ".yaml");
  if (!yaml) return false;
  const std::string image_name = stem.substr(stem.find_last_of('/') + 1) + ".pgm";
  yaml << "image: " << image_name << "\n"
       << "resolution: " << options_.resolution_m << "\n"
       << "origin: [" << origin_m_.x() << ", " << origin_m_.y() << ", 0.0]\n"
       << "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.25\nmode: trinary\n";
  return bool(yaml);
}

}  // namespace cairn
