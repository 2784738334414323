#pragma once
// What the web console serves: plain JSON and bytes prepared on the app thread from the merged map
// (MergedMap), so the HTTP threads never touch the mapper. LatestSnapshot hands the newest one across threads.
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "base_station/console/map_tiles.h"
#include "base_station/core/exploration.h"
#include "base_station/core/merged_map.h"
#include "base_station/core/operator_commands.h"

namespace cairn::base {

struct ConsoleSnapshot {
  nlohmann::json status = nlohmann::json::object();  ///< mission_time_s, mapped_area_m2, counts, alerts
  nlohmann::json robots = nlohmann::json::array();   ///< one entry per robot (see make_snapshot)
  nlohmann::json objects = nlohmann::json::array();  ///< one entry per merged object
  std::vector<uint8_t> map_png;
  GridCells grid_cells;  ///< the merged grid, for the map view's tiles
  /// The map view's switchable layers beyond the robots and objects: {"frontiers": [{x_m, y_m,
  /// length_m, saliency}], "saliency": {"cell_m", "cells": [[x_m, y_m, value]]}, "unreachable":
  /// [{x_m, y_m, robot, why}]} (the last filled by the base, which keeps the failed goals),
  /// "own_frames": {robot id: {"walls_m", "path_m"}} (unlinked robots' maps in their own frames).
  nlohmann::json layers = nlohmann::json::object();
  std::map<std::string, std::vector<uint8_t>> thumbnails;  ///< object key ("1-3") -> JPEG
  std::map<std::string, nlohmann::json> clouds;            ///< object key -> [[x,y,z,r,g,b],...]
  std::map<std::string, std::vector<uint8_t>> own_maps;    ///< unlinked robot id -> its own map (PNG)
  nlohmann::json map_image;  ///< map_png's geometry (map_image_geometry), sent with it as X-Map-Image
  nlohmann::json alert_log = nlohmann::json::array();  ///< every alert ever raised (AlertLog::log)
  CommandCheckContext command_context;                 ///< what a new command is checked against
};

struct SnapshotOptions {
  size_t max_trajectory_points = 500;  ///< per robot, decimated uniformly (last point kept)
  size_t max_cloud_points = 2000;      ///< per object
  size_t max_outline_points = 3000;    ///< per unlinked robot's own map (layers.own_frames)
  /// The map image (the report's, /api/map.png) and the unlinked robots' own maps (images and
  /// layers.own_frames): the dearest part of a snapshot. A quick snapshot between optimise ticks
  /// leaves them out (and keeps the last ones).
  bool render_images = true;
};

/// Builds a snapshot. `link_stats` is an object keyed by robot id as a decimal string (e.g. "1"),
/// each value free-form (the console shows "state", "bytes_rx" and "rtt_ms" when present); it is
/// copied into the robot's "link" field. With a `plan`, status["exploration"] lists each robot's
/// next goal and the map shows it. Must run on the thread that owns the mapper (MergedMap points into it).
ConsoleSnapshot make_snapshot(const MergedMap& merged, const nlohmann::json& link_stats,
                              const SnapshotOptions& options = {}, const ExplorationPlan* plan = nullptr);

/// One object for the console and the summary: id, frame ("global" or "robotN": its robot is not
/// placed yet, position_m is in that robot's own frame, and from_entry tells where), aliases, class,
/// confidence, position and its sigma, robots, reports, thumbnail and cloud URLs.
nlohmann::json object_json(const GlobalObject& o, const MergedMap& merged);

/// {"frontiers": n, "goals": [{"robot", "x_m", "y_m", "path_m", "frontier_m", "saliency"}], "idle": [robot ids],
///  "salient_cells": cells of the saliency layer of at least 0.1}
nlohmann::json exploration_json(const ExplorationPlan& plan);

/// The plan's frontiers and saliency cells (of at least 0.1) for the map view's layers.
nlohmann::json plan_layers_json(const ExplorationPlan& plan);

/// Thread-safe holder of the latest snapshot: the app publishes, the console reads.
class LatestSnapshot {
 public:
  void publish(ConsoleSnapshot snapshot) {
    auto next = std::make_shared<const ConsoleSnapshot>(std::move(snapshot));
    std::lock_guard<std::mutex> lock(mutex_);
    latest_ = std::move(next);
  }
  std::shared_ptr<const ConsoleSnapshot> get() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return latest_;
  }

 private:
  mutable std::mutex mutex_;
  std::shared_ptr<const ConsoleSnapshot> latest_ = std::make_shared<const ConsoleSnapshot>();
};

}  // namespace cairn::base
