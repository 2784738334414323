#include "base_station/core/map_consistency.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <unordered_set>

#include "common/check.h"
#include "common/laser_scan.h"
#include "common/occupancy_grid.h"

namespace cairn::base {
namespace {

struct Rendered {
  OccupancyGrid grid;
  /// Per cell of `grid` (row-major): 1 where a beam of at most wall_max_range_m ended.
  std::vector<uint8_t> close_hit;
  bool close(int col, int row) const { return close_hit.empty() || close_hit[size_t(row) * grid.width() + col]; }
};

Rendered render(const PlacedScans& side, const MapConsistencyOptions& o) {
  OccupancyGridOptions go;
  go.resolution_m = o.resolution_m;
  go.max_range_m = o.max_range_m;
  OccupancyGrid grid(go);
  std::vector<Eigen::Vector2d> close_hits_m;  // cells resolved once the grid has its final size
  const size_t n = std::min(side.keyframes.size(), side.T_frame_base.size());
  for (size_t k = 0; k < n; ++k) {
    const LaserScan& scan = side.keyframes[k]->scan;
    const std::vector<Eigen::Vector2f> points = scan_to_points(scan);
    if (o.wall_max_range_m > 0) {
      for (const auto& p : points) {
        if (p.norm() <= o.wall_max_range_m) close_hits_m.push_back(side.T_frame_base[k] * p.cast<double>());
      }
    }
    std::vector<Eigen::Vector2f> no_return;
    const float clear_m = float(std::min<double>(scan.range_max_m, o.max_range_m));
    for (size_t i = 0; i < scan.ranges_m.size(); ++i) {
      const float r = scan.ranges_m[i];
      if (std::isnan(r) || r < scan.range_max_m) continue;
      const float a = beam_angle_rad(scan, i);
      no_return.emplace_back(clear_m * std::cos(a), clear_m * std::sin(a));
    }
    grid.insert_scan(side.T_frame_base[k], points, no_return);
  }
  Rendered out{std::move(grid), {}};
  if (o.wall_max_range_m > 0) {
    out.close_hit.assign(size_t(out.grid.width()) * out.grid.height(), 0);
    for (const auto& p : close_hits_m) {
      const Eigen::Vector2i c = out.grid.cell_of(p);
      if (out.grid.contains(c.x(), c.y())) out.close_hit[size_t(c.y()) * out.grid.width() + c.x()] = 1;
    }
  }
  return out;
}

bool wall_near(const OccupancyGrid& grid, const Eigen::Vector2i& c, int radius_cells, float occupied) {
  for (int dr = -radius_cells; dr <= radius_cells; ++dr) {
    for (int dc = -radius_cells; dc <= radius_cells; ++dc) {
      if (dr * dr + dc * dc > radius_cells * radius_cells) continue;
      if (grid.log_odds(c.x() + dc, c.y() + dr) >= occupied) return true;
    }
  }
  return false;
}

/// Wall cells of `walls` inside `other`'s observed area, and those in its confident free space
/// (returned as cells of `walls`).
std::vector<Eigen::Vector2i> count(const Rendered& side, const OccupancyGrid& other, const MapConsistencyOptions& o,
                                   MapConsistencyResult* r) {
  const OccupancyGrid& walls = side.grid;
  const int radius = int(std::ceil(o.tolerance_m / o.resolution_m));
  std::vector<Eigen::Vector2i> contradicting;
  for (int row = 0; row < walls.height(); ++row) {
    for (int col = 0; col < walls.width(); ++col) {
      if (walls.log_odds(col, row) < o.occupied_log_odds || !side.close(col, row)) continue;
      const Eigen::Vector2i c = other.cell_of(walls.cell_center_m(col, row));
      const float v = other.log_odds(c.x(), c.y());
      if (v == 0.f) continue;  // unknown to the other side
      ++r->checked_cells;
      if (v <= o.free_log_odds && !wall_near(other, c, radius, o.occupied_log_odds))
        contradicting.emplace_back(col, row);
    }
  }
  r->contradicting_cells += int(contradicting.size());
  return contradicting;
}

/// The 8-connected pieces of `cells` (wall segments, not scattered noise).
std::vector<std::vector<Eigen::Vector2i>> pieces_of(const std::vector<Eigen::Vector2i>& cells) {
  std::set<std::pair<int, int>> left;
  for (const auto& c : cells) left.insert({c.x(), c.y()});
  std::vector<std::vector<Eigen::Vector2i>> out;
  while (!left.empty()) {
    std::vector<std::pair<int, int>> stack{*left.begin()};
    left.erase(left.begin());
    std::vector<Eigen::Vector2i> piece;
    while (!stack.empty()) {
      const auto [x, y] = stack.back();
      stack.pop_back();
      piece.emplace_back(x, y);
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          auto it = left.find({x + dx, y + dy});
          if (it == left.end()) continue;
          stack.push_back(*it);
          left.erase(it);
        }
      }
    }
    out.push_back(std::move(piece));
  }
  return out;
}

/// A piece of one side's wall in the other side's free space, and the other side's returned beams
/// through it: how many, and how many end on (within tolerance of) a wall of the piece's side.
struct Piece {
  int cells = 0;
  int beams = 0;
  int beams_on_walls = 0;
};

/// Counts `seer`'s beams that pass through the cell at `p_m` and return beyond it.
void count_beams_through(const PlacedScans& seer, const OccupancyGrid& walls, const Eigen::Vector2d& p_m,
                         const MapConsistencyOptions& o, Piece* piece) {
  const int radius = int(std::ceil(o.tolerance_m / o.resolution_m));
  const size_t n = std::min(seer.keyframes.size(), seer.T_frame_base.size());
  for (size_t k = 0; k < n; ++k) {
    const SE2& T = seer.T_frame_base[k];
    const LaserScan& scan = seer.keyframes[k]->scan;
    const Eigen::Vector2d d = p_m - T.translation();
    const double dist_m = d.norm();
    if (dist_m < 1e-6 || dist_m > o.max_range_m || scan.ranges_m.empty() || scan.angle_increment_rad <= 0) continue;
    // The beam nearest the cell's bearing (scans may wrap the full circle).
    const double bearing = normalize_angle(std::atan2(d.y(), d.x()) - T.yaw() - scan.angle_min_rad);
    long i = std::lround((bearing < 0 ? bearing + 2 * M_PI : bearing) / scan.angle_increment_rad);
    const long count = long(scan.ranges_m.size());
    if (i >= count && std::abs(count * scan.angle_increment_rad - 2 * M_PI) < 1e-3) i -= count;
    if (i < 0 || i >= count) continue;
    const float r = scan.ranges_m[size_t(i)];
    if (!std::isfinite(r) || r >= scan.range_max_m || r <= dist_m + o.resolution_m)
      continue;  // no return, or ends here
    const double a = T.yaw() + beam_angle_rad(scan, size_t(i));
    const Eigen::Vector2d end_m = T.translation() + double(r) * Eigen::Vector2d(std::cos(a), std::sin(a));
    ++piece->beams;
    piece->beams_on_walls += wall_near(walls, walls.cell_of(end_m), radius, o.occupied_log_odds);
  }
}

/// The pieces of `contradicting` (cells of `side`'s walls in the other side's free space); large
/// ones with the other side's beams through them counted.
std::vector<Piece> judge_pieces(const std::vector<Eigen::Vector2i>& contradicting, const Rendered& side,
                                const PlacedScans& other, const MapConsistencyOptions& o) {
  std::vector<Piece> out;
  for (const auto& cells : pieces_of(contradicting)) {
    Piece p;
    p.cells = int(cells.size());
    if (o.explained_min_fraction > 0 && p.cells >= o.max_contradiction_cluster_cells) {
      for (const auto& c : cells) count_beams_through(other, side.grid, side.grid.cell_center_m(c.x(), c.y()), o, &p);
    }
    out.push_back(p);
  }
  return out;
}

/// The largest piece not explained. A large piece is explained alone (enough beams, enough of
/// them on walls), or all are together when none with enough beams of its own is unexplained
/// and the pooled beams are.
int largest_unexplained(const std::vector<Piece>& all, const MapConsistencyOptions& o, int* explained) {
  auto is_large = [&](const Piece& p) { return p.cells >= o.max_contradiction_cluster_cells; };
  auto explains = [&](int beams, int on_walls) {
    return o.explained_min_fraction > 0 && beams >= o.explained_min_beams &&
           on_walls >= o.explained_min_fraction * beams;
  };
  int beams = 0, on_walls = 0;
  bool unexplained_alone = false;
  for (const Piece& p : all) {
    if (!is_large(p)) continue;
    beams += p.beams;
    on_walls += p.beams_on_walls;
    unexplained_alone |= p.beams >= o.explained_min_beams && !explains(p.beams, p.beams_on_walls);
  }
  const bool pooled = !unexplained_alone && explains(beams, on_walls);
  int largest = 0;
  for (const Piece& p : all) {
    if (is_large(p) && (pooled || explains(p.beams, p.beams_on_walls))) {
      ++*explained;
      continue;
    }
    largest = std::max(largest, p.cells);
  }
  return largest;
}

}  // namespace

PlacedScans select_near_keyframes(const PlacedScans& side, const Eigen::Vector2d& center_m,
                                  const MapConsistencyOptions& o) {
  CAIRN_CHECK(side.keyframes.size() == side.T_frame_base.size(), "PlacedScans with a pose per keyframe");
  const size_t n = side.keyframes.size();
  const double r2 =
      o.local_radius_m > 0 ? o.local_radius_m * o.local_radius_m : std::numeric_limits<double>::infinity();
  std::vector<std::pair<double, size_t>> near;  // squared distance, index
  for (size_t k = 0; k < n; ++k) {
    const double d2 = (side.T_frame_base[k].translation() - center_m).squaredNorm();
    if (d2 <= r2) near.emplace_back(d2, k);
  }
  std::sort(near.begin(), near.end());
  PlacedScans out;
  std::unordered_set<uint64_t> cells;
  const size_t cap = o.local_max_keyframes > 0 ? size_t(o.local_max_keyframes) : n;
  for (const auto& [d2, k] : near) {
    if (out.keyframes.size() >= cap) break;
    if (o.local_thin_cell_m > 0) {
      const Eigen::Vector2d p = (side.T_frame_base[k].translation() - center_m) / o.local_thin_cell_m;
      const uint64_t key =
          (uint64_t(uint32_t(int32_t(std::floor(p.x())))) << 32) | uint64_t(uint32_t(int32_t(std::floor(p.y()))));
      if (!cells.insert(key).second) continue;
    }
    out.keyframes.push_back(side.keyframes[k]);
    out.T_frame_base.push_back(side.T_frame_base[k]);
  }
  return out;
}

MapConsistencyResult check_map_consistency(const PlacedScans& a, const PlacedScans& b, const MapConsistencyOptions& o) {
  CAIRN_CHECK(a.keyframes.size() == a.T_frame_base.size() && b.keyframes.size() == b.T_frame_base.size(),
              "PlacedScans with a pose per keyframe");
  MapConsistencyResult r;
  if (a.keyframes.empty() || b.keyframes.empty()) {
    r.reason = "no keyframes on one side";
    return r;
  }
  const Rendered ra = render(a, o), rb = render(b, o);
  std::vector<Piece> all = judge_pieces(count(ra, rb.grid, o, &r), ra, b, o);
  for (const Piece& p : judge_pieces(count(rb, ra.grid, o, &r), rb, a, o)) all.push_back(p);
  r.largest_contradiction_cells = largest_unexplained(all, o, &r.explained_pieces);
  r.contradiction_ratio = r.checked_cells > 0 ? double(r.contradicting_cells) / r.checked_cells : 0.0;
  r.conclusive =
      r.checked_cells >= o.min_checked_cells || r.largest_contradiction_cells >= o.max_contradiction_cluster_cells;
  if (!r.conclusive) {
    r.reason = "inconclusive: " + std::to_string(r.checked_cells) + " overlapping wall cells";
    return r;
  }
  const std::string counts = std::to_string(r.contradicting_cells) + "/" + std::to_string(r.checked_cells) +
                             " wall cells in the other robot's free space, largest wall piece " +
                             std::to_string(r.largest_contradiction_cells) + " cells" +
                             (r.explained_pieces > 0 ? ", " + std::to_string(r.explained_pieces) + " explained" : "");
  if (r.contradiction_ratio > o.max_contradiction_ratio) {
    r.consistent = false;
    r.reason =
        "map contradiction " + std::to_string(int(std::lround(100 * r.contradiction_ratio))) + " % (" + counts + ")";
  } else if (r.largest_contradiction_cells >= o.max_contradiction_cluster_cells) {
    r.consistent = false;
    r.reason = "a wall where the other robot saw free space (" + counts + ")";
  }
  return r;
}

MapConsistencyImage draw_map_consistency(const PlacedScans& a, const PlacedScans& b, const MapConsistencyOptions& o) {
  MapConsistencyImage img;
  if (a.keyframes.empty() || b.keyframes.empty()) return img;
  const Rendered ra = render(a, o), rb = render(b, o);
  MapConsistencyResult unused;
  const std::vector<Eigen::Vector2i> ca = count(ra, rb.grid, o, &unused), cb = count(rb, ra.grid, o, &unused);
  const double res = o.resolution_m;
  auto corner = [&](const OccupancyGrid& g) -> Eigen::Vector2d {  // a value, not an Eigen expression of temporaries
    return g.origin_m() + Eigen::Vector2d(g.width(), g.height()) * res;
  };
  const Eigen::Vector2d lo = ra.grid.origin_m().cwiseMin(rb.grid.origin_m());
  const Eigen::Vector2d hi = corner(ra.grid).cwiseMax(corner(rb.grid));
  img.width = int(std::ceil((hi.x() - lo.x()) / res));
  img.height = int(std::ceil((hi.y() - lo.y()) / res));
  img.rgb.assign(size_t(img.width) * img.height * 3, 255);
  auto pixel = [&](const Eigen::Vector2d& p_m) -> uint8_t* {
    const int x = int(std::floor((p_m.x() - lo.x()) / res)),
              y = img.height - 1 - int(std::floor((p_m.y() - lo.y()) / res));
    if (x < 0 || y < 0 || x >= img.width || y >= img.height) return nullptr;
    return &img.rgb[(size_t(y) * img.width + x) * 3];
  };
  auto paint = [&](const Eigen::Vector2d& p_m, uint8_t r, uint8_t g, uint8_t b_) {
    if (uint8_t* px = pixel(p_m)) px[0] = r, px[1] = g, px[2] = b_;
  };
  // Free space: a takes red away, b takes blue away (both: green).
  for (const auto* side : {&ra, &rb}) {
    const OccupancyGrid& g = side->grid;
    const int channel = side == &ra ? 0 : 2;
    for (int row = 0; row < g.height(); ++row) {
      for (int col = 0; col < g.width(); ++col) {
        if (g.log_odds(col, row) > o.free_log_odds) continue;
        if (uint8_t* px = pixel(g.cell_center_m(col, row))) px[channel] = 200, px[1] = std::min<uint8_t>(px[1], 235);
      }
    }
  }
  for (const auto* side : {&ra, &rb}) {
    const OccupancyGrid& g = side->grid;
    for (int row = 0; row < g.height(); ++row) {
      for (int col = 0; col < g.width(); ++col) {
        if (g.log_odds(col, row) < o.occupied_log_odds) continue;
        if (side == &ra)
          paint(g.cell_center_m(col, row), 180, 0, 0);
        else
          paint(g.cell_center_m(col, row), 0, 0, 180);
      }
    }
  }
  for (const auto& c : ca) paint(ra.grid.cell_center_m(c.x(), c.y()), 0, 230, 0);
  for (const auto& c : cb) paint(rb.grid.cell_center_m(c.x(), c.y()), 255, 150, 0);
  for (const SE2& T : a.T_frame_base) paint(T.translation(), 120, 0, 140);
  for (const SE2& T : b.T_frame_base) paint(T.translation(), 0, 130, 130);
  return img;
}

}  // namespace cairn::base
