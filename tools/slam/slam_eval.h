#pragma once
// Accuracy of a 2D SLAM trajectory: absolute trajectory error after a best SE2 alignment and
// relative pose error against a reference (common/trajectory.h), a reference built from a corrected
// CARMEN log (matched to a raw log by identical scans when their timestamps differ), and the
// relations metric of Kuemmerle et al., "On measuring the accuracy of SLAM algorithms" (Autonomous
// Robots 2009): for each ground-truth relation (t1, t2, dx, dy, dyaw) the error of the estimated
// relative pose, reported as mean and standard deviation of the translational and rotational parts.
#include <optional>
#include <string>
#include <vector>

#include "common/carmen_log.h"
#include "common/trajectory.h"

namespace cairn::slam {

/// The corrected log's poses as a reference trajectory. With `raw`, each corrected scan is matched
/// to the raw scan with identical ranges (the corrected log keeps a subset, with coarse stamps) and
/// stamped with that raw scan's stamp; corrected scans without a twin are dropped. `scan_index`
/// receives, per reference pose, the index of its scan in `corrected.scans`.
Trajectory reference_from_corrected(const CarmenLog& corrected, const CarmenLog* raw = nullptr,
                                    int* unmatched = nullptr, std::vector<size_t>* scan_index = nullptr);

/// Estimate poses at the reference's stamps (exact stamp or interpolated within max_gap_ns).
Trajectory sample_at(const Trajectory& estimate, const Trajectory& reference_stamps, StampNs max_gap_ns);

struct Relation {
  double t1_s = 0, t2_s = 0;
  SE2 T_1_2;
};
/// `t1 t2 x y z roll pitch yaw` lines. Throws InputError naming the line when malformed.
std::vector<Relation> read_relations(const std::string& path);

/// Offset (s) to add to estimate stamps to get relation stamps: the most frequent difference between
/// relation stamps and estimate stamps, at 1 ms resolution.
double estimate_time_offset_s(const std::vector<Relation>& relations, const Trajectory& estimate);

struct RelationsError {
  int used = 0, total = 0;
  double trans_mean_m = 0, trans_sd_m = 0;
  double rot_mean_deg = 0, rot_sd_deg = 0;
};
/// Uses the relations whose both stamps fall on estimate stamps (within tolerance_s after offset).
RelationsError relations_error(const std::vector<Relation>& relations, const Trajectory& estimate, double offset_s,
                               double tolerance_s = 0.002);

}  // namespace cairn::slam
