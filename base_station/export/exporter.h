#pragma once
// Exports of the base station's state for the rescue team and for offline tools (DESIGN.md
// "Base station" 6): map.pgm + map.yaml, map.png, objects.geojson, objects.csv, object_<id>.ply,
// objects.bt (OctoMap), graph.g2o, trajectory_robot<N>.csv. OpenCV, PCL and OctoMap are used
// only here (the algorithm core links none of them). Never throws: every failure is reported with
// its path.
#include <cstdint>
#include <string>
#include <vector>

#include "base_station/core/exploration.h"
#include "base_station/core/merged_map.h"

namespace cairn::base {

struct ExportOptions {
  double octomap_resolution_m = 0.03;
  int png_min_size_px = 800;  ///< the map image is scaled up (integer factor) to about this size
  int png_max_scale = 8;
};

struct ExportedFile {
  std::string path;
  bool ok = false;
  std::string error;  ///< empty when ok
};

struct ExportSummary {
  std::vector<ExportedFile> files;
  bool ok() const {
    for (const auto& f : files)
      if (!f.ok) return false;
    return !files.empty();
  }
  int failures() const {
    int n = 0;
    for (const auto& f : files) n += f.ok ? 0 : 1;
    return n;
  }
};

/// Writes every export into out_dir (created if needed). With a `plan`, map.png shows where each
/// robot should search next.
ExportSummary export_all(const MergedMap& merged, const std::string& out_dir, const ExportOptions& options = {},
                         const ExplorationPlan* plan = nullptr);

/// The map image (grid, trajectories, keyframes, objects, and the plan's goals when given) as PNG
/// bytes; empty on failure.
std::vector<uint8_t> render_map_png(const MergedMap& merged, const ExportOptions& options = {},
                                    const ExplorationPlan* plan = nullptr);

/// Where render_map_png()'s pixels are on the map, so that a click on the image names a point:
/// pixel (u, v) (u right, v down, from the top-left corner) is at
/// (x0_m + u * m_per_px, y_top_m - v * m_per_px). valid = false for an empty map.
struct MapImageGeometry {
  bool valid = false;
  double x0_m = 0;
  double y_top_m = 0;
  double m_per_px = 0;
  int width_px = 0;
  int height_px = 0;
};
MapImageGeometry map_image_geometry(const OccupancyGrid& grid, const ExportOptions& options = {});

/// An unlinked robot's own map (robot_frame_objects.h) as PNG bytes, with its entry point and a
/// banner saying it is not placed yet; empty on failure.
std::vector<uint8_t> render_robot_frame_png(const RobotFrameMap& map, const ExportOptions& options = {});

/// Individual writers (used by export_all); each returns false and sets *error on failure.
/// The placed objects (global frame) and the unplaced ones (their robot's own frame, `frame` column /
/// property; GeoJSON features without geometry), each with its aliases and robot-frame position.
bool write_objects_geojson(const MergedMap& merged, const std::string& path, std::string* error);
bool write_objects_csv(const MergedMap& merged, const std::string& path, std::string* error);
/// VERTEX_SE2 / EDGE_SE2 (information upper triangle) / EDGE_PRIOR_SE2; vertex ids are a dense
/// index over the nodes in (robot, seq) order, listed in "# KEYFRAME <vertex> <robot> <seq>" lines.
/// Point nodes follow as VERTEX_XY ("# MARKER <vertex> <id>", "# OBJECT <vertex> <robot> <seq>") with
/// their range-bearing observations as EDGE_SE2_XY (point in the pose frame, information I11 I12 I22).
bool write_graph_g2o(const KeyframePoseGraph& graph, const std::string& path, std::string* error);
bool write_map_png(const MergedMap& merged, const std::string& path, const ExportOptions& options, std::string* error,
                   const ExplorationPlan* plan = nullptr);
bool write_robot_frame_png(const RobotFrameMap& map, const std::string& path, const ExportOptions& options,
                           std::string* error);
/// Any row-major RGB picture (top row first, 3 bytes per pixel) as PNG, e.g. draw_map_consistency's.
bool write_rgb_png(int width, int height, const std::vector<uint8_t>& rgb, const std::string& path, std::string* error);
bool write_object_ply(const GlobalObject& object, const std::string& path, std::string* error);
bool write_objects_octomap(const std::vector<GlobalObject>& objects, double resolution_m, const std::string& path,
                           std::string* error);

}  // namespace cairn::base
