#pragma once
// Diagnostics of the merger's place recognition on a split log (tests/multirobot): replays the
// robots' keyframes through a KeyframeLoopCloser in the order merge() feeds them and counts, per robot
// pair, how many queries had a true inter-robot neighbour (reference poses within a radius) and
// how many of those kept a true candidate at each stage: ring-key pre-selection, Scan Context
// distance, verification tried, verified (and verified closures that disagree with the reference).
#include <string>
#include <vector>

#include "base_station/core/keyframe_loop_closer.h"
#include "tests/multirobot/split_run.h"

namespace cairn::multirobot {

struct FunnelRow {
  RobotId a, b;               ///< a < b
  int queries_with_true = 0;  ///< queries with another robot's keyframe within true_radius_m
  int ring_key = 0;           ///< ... a true one among the ring-key candidates
  int descriptor = 0;         ///< ... among those below the descriptor distance
  int tried = 0;              ///< ... among those verified
  int verified_true = 0;      ///< ... verified and agreeing with the reference (0.3 m / 5 deg)
  int verified_wrong = 0;     ///< verified closures (any query) off the reference
};

/// One row per robot pair, replaying detection every `optimize_every` keyframes like merge().
std::vector<FunnelRow> loop_funnel(const std::vector<RobotRun>& runs, const base::KeyframeLoopCloserOptions& options,
                                   double true_radius_m = 2.0, int optimize_every = 25);
std::string to_string(const FunnelRow& row);

}  // namespace cairn::multirobot
