#include "common/grid_planning.h"

#include <algorithm>
#include <cmath>
#include <queue>

#include "common/check.h"

namespace cairn {
namespace {

/// Log odds of a probability: comparing log odds saves an exp() per cell.
double logit(double p) {
  if (p <= 0.0) return -std::numeric_limits<double>::infinity();
  if (p >= 1.0) return std::numeric_limits<double>::infinity();
  return std::log(p / (1.0 - p));
}

}  // namespace

PlanningGrid::PlanningGrid(const OccupancyGrid& map, const GridPlanningOptions& options,
                           const std::vector<Eigen::Vector2d>& include_m)
    : options_(options), map_origin_m_(map.origin_m()), map_res_(map.resolution_m()) {
  k_ = options.cell_m > map_res_ ? std::max(1, int(std::lround(options.cell_m / map_res_))) : 1;
  res_ = map_res_ * k_;
  // The box: known cells and the points to include, in map cells.
  int col_lo = INT32_MAX, row_lo = INT32_MAX, col_hi = INT32_MIN, row_hi = INT32_MIN;
  auto extend = [&](int c, int r) {
    col_lo = std::min(col_lo, c);
    row_lo = std::min(row_lo, r);
    col_hi = std::max(col_hi, c);
    row_hi = std::max(row_hi, r);
  };
  for (int r = 0; r < map.height(); ++r) {
    for (int c = 0; c < map.width(); ++c) {
      if (map.known(c, r)) extend(c, r);
    }
  }
  for (const Eigen::Vector2d& p : include_m) {
    const Eigen::Vector2i cell = map.cell_of(p);
    extend(cell.x(), cell.y());
  }
  if (col_hi < col_lo) return;  // nothing known, nothing to include: an empty grid
  const int margin = std::max(1, int(std::ceil(options.margin_m / res_ - 1e-9))) * k_;  // map cells
  col0_ = col_lo - margin;
  row0_ = row_lo - margin;
  w_ = (col_hi + margin - col0_) / k_ + 1;
  h_ = (row_hi + margin - row0_) / k_ + 1;
  classify(map, k_);
  if (!options.graded_clearance) near_wall_ = dilate_square(std::max(0, int(std::ceil(options.clearance_m / res_))));
  inflation_m_ = options.inflation_m > 0.0 ? float(options.inflation_m) : -1.f;
  wall_distance_m_ =
      wall_distances(std::max(options.inflation_m, options.graded_clearance ? options.clearance_m : 0.0));
  summarise();
}

void PlanningGrid::summarise() {
  traversable_.assign(cells_.size(), 0);
  step_factor_.assign(cells_.size(), 1.f);
  const GridPlanningOptions& o = options_;
  for (size_t i = 0; i < cells_.size(); ++i) {
    traversable_[i] =
        !blocked(i) && (cells_[i] == CellState::kFree || (cells_[i] == CellState::kUnknown && o.unknown_cost > 0.0));
    double near = 1.0;
    if (o.graded_clearance) {
      const double d = wall_distance_m(i);
      if (d < o.clearance_m) near = 1.0 + (o.near_wall_cost - 1.0) * (1.0 - d / o.clearance_m);
    } else if (near_wall_[i]) {
      near = o.near_wall_cost;
    }
    step_factor_[i] = float(cells_[i] == CellState::kUnknown ? near * o.unknown_cost : near);
  }
}

void PlanningGrid::classify(const OccupancyGrid& map, int k) {
  const double occupied_lo = logit(options_.occupied_above), free_lo = logit(options_.free_below);
  cells_.assign(size_t(w_) * h_, CellState::kUnknown);
  for (int r = 0; r < h_; ++r) {
    for (int c = 0; c < w_; ++c) {
      bool any_free = false, any_occupied = false;
      for (int dr = 0; dr < k && !any_occupied; ++dr) {
        for (int dc = 0; dc < k; ++dc) {
          const int mc = col0_ + c * k + dc, mr = row0_ + r * k + dr;
          const float lo = map.log_odds(mc, mr);  // 0: unknown, also outside the map
          if (lo == 0.f) continue;
          any_occupied = any_occupied || lo > occupied_lo;
          any_free = any_free || lo < free_lo;
        }
      }
      cells_[index(c, r)] = any_occupied ? CellState::kOccupied : any_free ? CellState::kFree : CellState::kUnknown;
    }
  }
}

std::vector<uint8_t> PlanningGrid::dilate_square(int k) const {
  std::vector<uint8_t> rows(cells_.size(), 0);
  for (int r = 0; r < h_; ++r) {
    int last_wall = -1000000;
    for (int c = 0; c < w_; ++c) {
      if (cells_[index(c, r)] == CellState::kOccupied) last_wall = c;
      if (c - last_wall <= k) rows[index(c, r)] = 1;
    }
    last_wall = 1000000;
    for (int c = w_ - 1; c >= 0; --c) {
      if (cells_[index(c, r)] == CellState::kOccupied) last_wall = c;
      if (last_wall - c <= k) rows[index(c, r)] = 1;
    }
  }
  std::vector<uint8_t> out(cells_.size(), 0);
  for (int c = 0; c < w_; ++c) {
    int last = -1000000;
    for (int r = 0; r < h_; ++r) {
      if (rows[index(c, r)]) last = r;
      if (r - last <= k) out[index(c, r)] = 1;
    }
    last = 1000000;
    for (int r = h_ - 1; r >= 0; --r) {
      if (rows[index(c, r)]) last = r;
      if (last - r <= k) out[index(c, r)] = 1;
    }
  }
  return out;
}

std::vector<float> PlanningGrid::wall_distances(double radius_m) const {
  if (radius_m <= 0.0) return {};
  std::vector<float> out(cells_.size(), std::numeric_limits<float>::infinity());
  const double radius_cells = radius_m / res_;
  const int k = int(std::floor(radius_cells));
  struct Offset {
    int dc, dr;
    float distance_m;
  };
  std::vector<Offset> disc;
  for (int dr = -k; dr <= k; ++dr) {
    for (int dc = -k; dc <= k; ++dc) {
      if (dc * dc + dr * dr <= radius_cells * radius_cells) disc.push_back({dc, dr, float(res_ * std::hypot(dc, dr))});
    }
  }
  auto occupied = [&](int c, int r) { return !in(c, r) || cells_[index(c, r)] == CellState::kOccupied; };
  for (int r = 0; r < h_; ++r) {
    for (int c = 0; c < w_; ++c) {
      // Only occupied cells with a non-occupied 4-neighbour: the occupied cell nearest to any
      // other cell is one of them (a step towards that cell would otherwise be nearer).
      if (!occupied(c, r) || (occupied(c + 1, r) && occupied(c - 1, r) && occupied(c, r + 1) && occupied(c, r - 1))) {
        continue;
      }
      for (const Offset& d : disc) {
        if (!in(c + d.dc, r + d.dr)) continue;
        float& v = out[index(c + d.dc, r + d.dr)];
        v = std::min(v, d.distance_m);
      }
    }
  }
  return out;
}

Eigen::Vector2d PlanningGrid::centre_m(const Eigen::Vector2i& cell) const {
  return map_origin_m_ +
         map_res_ * Eigen::Vector2d(double(col0_ + cell.x() * k_) + 0.5 * k_, double(row0_ + cell.y() * k_) + 0.5 * k_);
}

Eigen::Vector2i PlanningGrid::cell_of(const Eigen::Vector2d& p_m) const {
  const Eigen::Vector2d c = (p_m - map_origin_m_) / map_res_;
  const int mc = int(std::floor(c.x())) - col0_, mr = int(std::floor(c.y())) - row0_;
  // Floor division: a point left of or below the box gets a negative cell.
  auto floor_div = [](int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); };
  return {floor_div(mc, k_), floor_div(mr, k_)};
}

void PlanningGrid::forbid(const KeepOutPolygon& area) {
  const Eigen::Vector2i lo = cell_of(area.min_m()).cwiseMax(Eigen::Vector2i(0, 0));
  const Eigen::Vector2i hi = cell_of(area.max_m()).cwiseMin(Eigen::Vector2i(w_ - 1, h_ - 1));
  for (int r = lo.y(); r <= hi.y(); ++r)
    for (int c = lo.x(); c <= hi.x(); ++c) {
      if (area.contains(centre_m({c, r}))) traversable_[index(c, r)] = 0;
    }
}

bool PlanningGrid::is_frontier(int c, int r) const {
  if (cells_[index(c, r)] != CellState::kFree) return false;
  constexpr int kN[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  for (const auto& d : kN) {
    const int cc = c + d[0], rr = r + d[1];
    if (!in(cc, rr) || cells_[index(cc, rr)] == CellState::kUnknown) return true;
  }
  return false;
}

std::vector<FrontierPiece> frontier_pieces(const PlanningGrid& g) {
  std::vector<uint8_t> seen(g.size(), 0);
  std::vector<FrontierPiece> pieces;
  for (int r = 0; r < g.height(); ++r) {
    for (int c = 0; c < g.width(); ++c) {
      if (seen[g.index(c, r)] || !g.is_frontier(c, r)) continue;
      FrontierPiece piece{{c, r}};
      seen[g.index(c, r)] = 1;
      for (size_t i = 0; i < piece.size(); ++i) {
        for (int dr = -1; dr <= 1; ++dr) {
          for (int dc = -1; dc <= 1; ++dc) {
            const int cc = piece[i].x() + dc, rr = piece[i].y() + dr;
            if (!g.in(cc, rr) || seen[g.index(cc, rr)] || !g.is_frontier(cc, rr)) continue;
            seen[g.index(cc, rr)] = 1;
            piece.emplace_back(cc, rr);
          }
        }
      }
      pieces.push_back(std::move(piece));
    }
  }
  return pieces;
}

std::optional<Eigen::Vector2i> nearest_traversable(const PlanningGrid& g, const Eigen::Vector2i& cell,
                                                   double radius_m) {
  const int k = int(std::ceil(radius_m / g.resolution_m()));
  double best = std::numeric_limits<double>::infinity();
  std::optional<Eigen::Vector2i> found;
  for (int dr = -k; dr <= k; ++dr) {
    for (int dc = -k; dc <= k; ++dc) {
      const int c = cell.x() + dc, r = cell.y() + dr;
      const double d = std::hypot(dc, dr);
      if (d < best && g.in(c, r) && g.traversable(g.index(c, r))) {
        best = d;
        found = Eigen::Vector2i(c, r);
      }
    }
  }
  return found;
}

DistanceField path_lengths(const PlanningGrid& g, const Eigen::Vector2i& start_cell, double start_search_m,
                           const std::optional<Eigen::Vector2i>& stop_at) {
  DistanceField field;
  field.length_m.assign(g.size(), DistanceField::kUnreached);
  field.parent.assign(g.size(), -1);
  if (g.empty()) return field;
  Eigen::Vector2i start = start_cell;
  if (!g.in(start) || !g.traversable(g.index(start))) {
    const std::optional<Eigen::Vector2i> found = nearest_traversable(g, start, start_search_m);
    if (!found) return field;
    start = *found;
  }
  field.start = start;
  const double res = g.resolution_m();
  const size_t stop = stop_at && g.in(*stop_at) ? g.index(*stop_at) : g.size();
  std::vector<double>& dist = field.length_m;
  using Item = std::pair<double, size_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  int64_t farthest2 = 0;  // squared cells, from the start
  dist[g.index(start)] = 0;
  queue.push({0.0, g.index(start)});
  while (!queue.empty()) {
    const auto [d, i] = queue.top();
    queue.pop();
    if (d > dist[i]) continue;
    if (i == stop) break;
    const int c = int(i % g.width()), r = int(i / g.width());
    farthest2 =
        std::max(farthest2, int64_t(c - start.x()) * (c - start.x()) + int64_t(r - start.y()) * (r - start.y()));
    for (int dr = -1; dr <= 1; ++dr) {
      for (int dc = -1; dc <= 1; ++dc) {
        const int cc = c + dc, rr = r + dr;
        if ((dc == 0 && dr == 0) || !g.in(cc, rr)) continue;
        const size_t j = g.index(cc, rr);
        if (!g.traversable(j)) continue;
        const double step = res * (dc && dr ? M_SQRT2 : 1.0) * g.step_factor(j);
        if (d + step < dist[j]) {
          dist[j] = d + step;
          field.parent[j] = int32_t(i);
          queue.push({dist[j], j});
        }
      }
    }
  }
  field.farthest_m = res * std::sqrt(double(farthest2));
  return field;
}

std::vector<Eigen::Vector2d> extract_path_m(const PlanningGrid& g, const DistanceField& field,
                                            const Eigen::Vector2i& goal) {
  CAIRN_CHECK(field.length_m.size() == g.size() && field.parent.size() == g.size(), "a search of another grid");
  std::vector<Eigen::Vector2d> path;
  if (!g.in(goal) || !field.reached(g.index(goal))) return path;
  for (int32_t i = int32_t(g.index(goal)); i >= 0; i = field.parent[size_t(i)]) {
    path.push_back(g.centre_m(g.cell(size_t(i))));
    CAIRN_CHECK(path.size() <= g.size(), "the parents of a search form a cycle");
  }
  std::reverse(path.begin(), path.end());
  return path;
}

PieceReach nearest_cell_of(const FrontierPiece& piece, const PlanningGrid& g, const DistanceField& field) {
  CAIRN_CHECK(field.length_m.size() == g.size(), "a search of another grid");
  PieceReach best;
  for (const Eigen::Vector2i& cell : piece) {
    const double d = field.length_m[g.index(cell)];
    if (d < best.path_m) {
      best.path_m = d;
      best.cell = cell;
    }
  }
  return best;
}

std::optional<FrontierTarget> nearest_frontier(const PlanningGrid& g, const DistanceField& field,
                                               const std::vector<FrontierPiece>& pieces,
                                               const NearestFrontierOptions& o,
                                               const std::function<bool(const Eigen::Vector2d&)>& skip) {
  CAIRN_CHECK(field.length_m.size() == g.size(), "a search of another grid");
  std::optional<FrontierTarget> best;
  for (size_t p = 0; p < pieces.size(); ++p) {
    if (int(pieces[p].size()) < o.min_piece_cells) continue;
    for (const Eigen::Vector2i& cell : pieces[p]) {
      const double d = field.length_m[g.index(cell)];
      if (!field.reached(g.index(cell)) || d < o.min_path_m || (best && d >= best->path_m)) continue;
      const Eigen::Vector2d position_m = g.centre_m(cell);
      if (skip && skip(position_m)) continue;
      best = FrontierTarget{int(p), cell, position_m, d};
    }
  }
  return best;
}

}  // namespace cairn
