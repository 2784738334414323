#include "base_station/core/sightings.h"

#include <array>
#include <cmath>
#include <iterator>

#include "base_station/core/mapper_data.h"
#include "common/robot_markers.h"

namespace cairn::base {

std::vector<Sighting> sightings_in(const Keyframe& kf, int* invalid) {
  std::vector<Sighting> out;
  for (const LandmarkObservation& o : kf.landmarks) {
    const std::optional<RobotId> seen = robot_of_marker(o.id);
    if (!seen) continue;
    if (*seen == kf.id.robot || !validate_landmark_observation(o).empty()) {
      if (invalid) ++*invalid;
      continue;
    }
    out.push_back(Sighting{kf.id, *seen, o});
  }
  return out;
}

std::optional<SeenPosition> position_at(const MapperData& data, RobotId robot, StampNs stamp_ns, double min_offset_m) {
  const Keyframe* before = nullptr;
  const Keyframe* after = nullptr;
  for (const auto& [id, kf] : data.robot_keyframes(robot)) {
    if (kf.stamp_ns <= stamp_ns) before = &kf;
    if (kf.stamp_ns >= stamp_ns) {
      after = &kf;
      break;
    }
  }
  if (before == nullptr || after == nullptr || after->id.seq - before->id.seq > 1) return std::nullopt;
  // Linear in the relative motion between the two keyframes (a short, locally exact stretch).
  const SE2 T_before_after = before->T_local_base.inverse() * after->T_local_base;
  const double span_ns = double(after->stamp_ns - before->stamp_ns);
  const double s = span_ns > 0.0 ? double(stamp_ns - before->stamp_ns) / span_ns : 0.0;
  const Eigen::Vector2d in_before = s * T_before_after.translation();
  const SeenPosition from_before{before->id, in_before};
  const SeenPosition from_after{after->id, T_before_after.inverse() * in_before};
  for (const SeenPosition& p : s <= 0.5 ? std::array{from_before, from_after} : std::array{from_after, from_before}) {
    if (p.point_m.norm() >= min_offset_m) return p;
  }
  return std::nullopt;
}

bool has_keyframe_after(const MapperData& data, RobotId robot, StampNs stamp_ns) {
  const RobotKeyframes kfs = data.robot_keyframes(robot);
  return !kfs.empty() && std::prev(kfs.end())->second.stamp_ns >= stamp_ns;
}

namespace {

/// Sighting `s` as correspondence `index`: the seen point in the observer's frame and the seen robot's.
void add_correspondence(const MapperData& data, const Sighting& s, int index, LocalLandmarks* observer_side,
                        LocalLandmarks* seen_side) {
  const std::optional<SeenPosition> seen = position_at(data, s.seen, s.observation.stamp_ns);
  if (!seen) return;
  const Keyframe& observer = data.keyframe(s.observer);
  const Keyframe& seen_kf = data.keyframe(seen->keyframe);
  LocalLandmark& o = (*observer_side)[LandmarkId(index)];
  o.sum_m = observer.T_local_base * s.observation.point_m();
  o.observations = 1;
  o.nearest = s.observer;
  o.nearest_range_m = s.observation.range_m;
  LocalLandmark& b = (*seen_side)[LandmarkId(index)];
  b.sum_m = seen_kf.T_local_base * seen->point_m;
  b.observations = 1;
  b.nearest = seen->keyframe;
  b.nearest_range_m = seen->point_m.norm();
}

}  // namespace

void sighting_correspondences(const MapperData& data, RobotId a, RobotId b, LocalLandmarks* in_a,
                              LocalLandmarks* in_b) {
  in_a->clear();
  in_b->clear();
  for (size_t i = 0; i < data.sightings.size(); ++i) {
    const Sighting& s = data.sightings[i];
    if (s.observer.robot == a && s.seen == b) add_correspondence(data, s, int(i), in_a, in_b);
    if (s.observer.robot == b && s.seen == a) add_correspondence(data, s, int(i), in_b, in_a);
  }
}

}  // namespace cairn::base
