#pragma once
// Strong identifier types. Never pack ids into bits: each id is a small struct.
#include <cstdint>
#include <functional>
#include <ostream>
#include <string>

namespace cairn {

/// One robot of the team. Values are small non-negative integers (0, 1, 2, ...).
struct RobotId {
  int32_t value = -1;
  constexpr RobotId() = default;
  constexpr explicit RobotId(int32_t v) : value(v) {}
  constexpr bool valid() const { return value >= 0; }
  friend constexpr bool operator==(RobotId a, RobotId b) { return a.value == b.value; }
  friend constexpr bool operator!=(RobotId a, RobotId b) { return a.value != b.value; }
  friend constexpr bool operator<(RobotId a, RobotId b) { return a.value < b.value; }
};

/// A keyframe: the robot that made it and its sequence number on that robot (0, 1, 2, ...).
struct KeyframeId {
  RobotId robot;
  int32_t seq = -1;
  friend constexpr bool operator==(KeyframeId a, KeyframeId b) { return a.robot == b.robot && a.seq == b.seq; }
  friend constexpr bool operator!=(KeyframeId a, KeyframeId b) { return !(a == b); }
  friend constexpr bool operator<(KeyframeId a, KeyframeId b) {
    return a.robot != b.robot ? a.robot < b.robot : a.seq < b.seq;
  }
};

/// An object of interest as first reported by one robot (the base may merge several).
struct ObjectId {
  RobotId robot;
  int32_t seq = -1;
  friend constexpr bool operator==(ObjectId a, ObjectId b) { return a.robot == b.robot && a.seq == b.seq; }
  friend constexpr bool operator!=(ObjectId a, ObjectId b) { return !(a == b); }
  friend constexpr bool operator<(ObjectId a, ObjectId b) {
    return a.robot != b.robot ? a.robot < b.robot : a.seq < b.seq;
  }
};

/// A landmark's identity (marker id). Small non-negative integers; the same for every robot.
struct LandmarkId {
  int32_t value = -1;
  constexpr LandmarkId() = default;
  constexpr explicit LandmarkId(int32_t v) : value(v) {}
  constexpr bool valid() const { return value >= 0; }
  friend constexpr bool operator==(LandmarkId a, LandmarkId b) { return a.value == b.value; }
  friend constexpr bool operator!=(LandmarkId a, LandmarkId b) { return a.value != b.value; }
  friend constexpr bool operator<(LandmarkId a, LandmarkId b) { return a.value < b.value; }
};

inline std::string to_string(RobotId id) { return "robot" + std::to_string(id.value); }
inline std::string to_string(KeyframeId id) { return to_string(id.robot) + "/kf" + std::to_string(id.seq); }
inline std::string to_string(ObjectId id) { return to_string(id.robot) + "/obj" + std::to_string(id.seq); }
inline std::string to_string(LandmarkId id) { return "landmark" + std::to_string(id.value); }
inline std::ostream& operator<<(std::ostream& os, RobotId id) { return os << to_string(id); }
inline std::ostream& operator<<(std::ostream& os, KeyframeId id) { return os << to_string(id); }
inline std::ostream& operator<<(std::ostream& os, ObjectId id) { return os << to_string(id); }

}  // namespace cairn

template <>
struct std::hash<cairn::RobotId> {
  size_t operator()(cairn::RobotId id) const noexcept { return std::hash<int32_t>()(id.value); }
};
template <>
struct std::hash<cairn::KeyframeId> {
  size_t operator()(cairn::KeyframeId id) const noexcept {
    return std::hash<int64_t>()((int64_t(id.robot.value) << 32) ^ uint32_t(id.seq));
  }
};
template <>
struct std::hash<cairn::ObjectId> {
  size_t operator()(cairn::ObjectId id) const noexcept {
    return std::hash<int64_t>()((int64_t(id.robot.value) << 32) ^ uint32_t(id.seq));
  }
};
template <>
struct std::hash<cairn::LandmarkId> {
  size_t operator()(cairn::LandmarkId id) const noexcept { return std::hash<int32_t>()(id.value); }
};
