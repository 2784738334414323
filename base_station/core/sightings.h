#pragma once
// Robots seeing robots: a teammate's marker (common/robot_markers.h) seen by robot A's camera is a
// range-bearing measurement of robot B's position at that time, from A's keyframe. Paired with B's
// own pose at the same stamp (interpolated between B's keyframes), each sighting is one point known
// in both robots' frames, the same kind of correspondence two robots' shared fixed markers give;
// so a pair's sightings (either way round) are aligned and judged exactly like shared markers
// (landmarks.h align_landmarks, then RobotLinker's map check). Mutual sightings or a robot seen
// while it moves span the distance the rotation needs; a robot seen standing still does not, and
// is refused for too little spread.
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "base_station/core/landmarks.h"
#include "common/ids.h"
#include "common/keyframe.h"
#include "common/landmark_observation.h"

namespace cairn::base {

struct MapperData;

struct Sighting {
  KeyframeId observer;  ///< the observing robot's keyframe the observation is expressed from
  RobotId seen;
  LandmarkObservation observation;  ///< stamp_ns: when it was seen
};

/// The sightings in a keyframe's landmark observations (robot-marker ids, another robot than the
/// keyframe's, valid values); `invalid` (may be null) counts the dropped ones.
std::vector<Sighting> sightings_in(const Keyframe& kf, int* invalid);

/// Where `robot` was at `stamp_ns`, as a point in the frame of one of the two keyframes around the
/// stamp (interpolated between them by their front-end poses): the one nearer in time, unless the
/// point is closer than `min_offset_m` to it (a range-bearing edge needs a bearing), then the other.
/// nullopt while the robot has no keyframe at or after the stamp yet, or none at or before it, when
/// neither keyframe is min_offset_m away, or when keyframes between the two are missing (a straight
/// line across the gap is no position; a long wait between two consecutive keyframes is fine: the
/// robot stood still).
struct SeenPosition {
  KeyframeId keyframe;
  Eigen::Vector2d point_m;
};
std::optional<SeenPosition> position_at(const MapperData& data, RobotId robot, StampNs stamp_ns,
                                        double min_offset_m = 0.0);
/// Whether `robot` has a keyframe at or after the stamp (position_at can then decide for good).
bool has_keyframe_after(const MapperData& data, RobotId robot, StampNs stamp_ns);

/// The pair's sightings (a seeing b and b seeing a) as point correspondences: entry i of *a and *b
/// is the same point, in a's and b's local frames (front-end poses, as accumulate_landmarks), with
/// the keyframes nearest to it. Sightings whose seen robot has no pose at that stamp yet are skipped.
void sighting_correspondences(const MapperData& data, RobotId a, RobotId b, LocalLandmarks* in_a, LocalLandmarks* in_b);

}  // namespace cairn::base
