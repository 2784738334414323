#pragma once
// The operator's keep-out areas: rectangles on the merged map (KeepOutArea, drawn on the console
// and kept by base_station/core/search_controls.h), and the same areas in one robot's own frame
// (KeepOutPolygon: the rectangle turned, as its four corners), which the base sends to that robot
// so its own planner and its own exploration keep out too. Pure.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/ids.h"
#include "common/se2.h"

namespace cairn {

struct KeepOutArea {
  uint32_t id = 0;
  Eigen::Vector2d min_m{0, 0};  ///< merged map frame
  Eigen::Vector2d max_m{0, 0};
  bool contains(const Eigen::Vector2d& p_m) const {
    return (p_m.array() >= min_m.array()).all() && (p_m.array() <= max_m.array()).all();
  }
};

/// A keep-out area in another frame: a convex quadrilateral, its corners in order (either winding).
struct KeepOutPolygon {
  uint32_t id = 0;
  std::array<Eigen::Vector2d, 4> corners_m{};
  /// Inside or on an edge.
  bool contains(const Eigen::Vector2d& p_m) const;
  Eigen::Vector2d min_m() const;  ///< bounding box
  Eigen::Vector2d max_m() const;
};

/// `area`'s corners carried into another frame by `T_frame_map` (for a robot: T_local_global).
KeepOutPolygon in_frame(const KeepOutArea& area, const SE2& T_frame_map);

/// Why `polygon` cannot be a keep-out area (a corner not finite, corners not in convex order, no
/// area); nullopt when it can.
std::optional<std::string> polygon_fault(const KeepOutPolygon& polygon);

/// The areas one robot is told, in its own frame.
struct KeepOutMessage {
  RobotId robot{0};
  /// Grows with every change of the operator's areas; the robot reports the version it holds.
  uint32_t version = 0;
  std::vector<KeepOutPolygon> areas;
};

/// `p` with every edge moved `margin_m` outward (a convex polygon stays convex).
KeepOutPolygon grown(const KeepOutPolygon& p, double margin_m);

/// Where a robot standing at p_m may not go: each area grown by `margin_m` (the robot's radius: its
/// body keeps out, not only its centre). An area it already stands in does not trap it (it may drive
/// out), and one whose margin it stands in is closed without the margin.
std::vector<KeepOutPolygon> closed_around(const std::vector<KeepOutPolygon>& areas, const Eigen::Vector2d& p_m,
                                          double margin_m = 0.0);

}  // namespace cairn
