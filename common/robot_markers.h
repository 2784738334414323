#pragma once
// The team's robot markers: every robot carries a coloured mark (the paper's "red round mark" idea,
// one hue per robot) that the other robots' RGB-D object pipeline recognises. A sighting of robot B
// by robot A is carried like an identified landmark (common/landmark_observation.h) with the
// reserved id robot_marker_landmark(B): a landmark that moves with its robot, so the base station
// never treats it as a fixed marker (base_station/core/sightings.h turns it into a range-bearing
// constraint between A's and B's poses at that time).
// Hues are chosen apart from the objects' classes (victim red/orange 0-16 and 170-180, hazard yellow
// 20-35, exit green 45-85, OpenCV's 0-180 scale), 18 hue units from each other.
#include <array>
#include <cstdint>
#include <optional>

#include "common/ids.h"

namespace cairn {

struct RobotMarker {
  RobotId robot;
  std::array<uint8_t, 3> color_rgb;
  int hue;  ///< OpenCV hue (0..180) of color_rgb
};

/// The marked robots (ids 0-3): a larger team needs a coded marker (a fiducial), not one hue each.
inline constexpr std::array<RobotMarker, 4> kRobotMarkers{{
    {RobotId(0), {{20, 180, 220}}, 96},   // azure
    {RobotId(1), {{30, 83, 230}}, 112},   // blue
    {RobotId(2), {{87, 20, 220}}, 130},   // violet
    {RobotId(3), {{200, 20, 200}}, 150},  // magenta
}};

/// Landmark ids from here up are robots' markers, never fixed landmarks.
inline constexpr int32_t kRobotMarkerLandmarkBase = 1'000'000;

inline std::optional<RobotMarker> robot_marker(RobotId robot) {
  for (const RobotMarker& m : kRobotMarkers) {
    if (m.robot == robot) return m;
  }
  return std::nullopt;
}

inline LandmarkId robot_marker_landmark(RobotId robot) { return LandmarkId(kRobotMarkerLandmarkBase + robot.value); }

/// The robot whose marker `id` is; nullopt for a fixed landmark.
inline std::optional<RobotId> robot_of_marker(LandmarkId id) {
  if (id.value < kRobotMarkerLandmarkBase) return std::nullopt;
  return RobotId(id.value - kRobotMarkerLandmarkBase);
}

}  // namespace cairn
