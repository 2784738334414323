#pragma once
// LAGO-style initialisation of an SE2 pose graph (Carlone, Aragues, Castellanos, Bona, "A linear
// approximation for graph-based simultaneous localization and mapping", RSS 2011 / IJRR 2014;
// the "LagoSLAM" the paper lists): closed-form, no initial guess needed.
//  1. Orientations: yaw along a breadth-first spanning tree gives each edge its 2*pi wrap
//     (regularisation); then linear least squares over all edges, theta_j - theta_i = delta_ij,
//     weighted by the yaw information.
//  2. Positions: with the orientations fixed, p_j - p_i = R(theta_i) t_ij is linear; solved by
//     least squares weighted by the rotated translation information.
// The result is the initial guess of the nonlinear Ceres solve: it lands in the basin of the
// global optimum on graphs where odometry composition does not (e.g. M3500 from odometry).
#include <map>
#include <optional>
#include <vector>

#include "base_station/core/keyframe_pose_graph.h"

namespace cairn::base {

struct LagoOptions {
  /// Weight (information) of an anchor's pose; anchors are the priors of the graph, or the first
  /// node when there is none.
  double anchor_information = 1e8;
};

/// Estimates every node connected to an anchor; nodes in components without one are fixed by
/// their first node at its current estimate. nullopt if the linear systems are singular.
std::optional<std::map<KeyframeId, SE2>> lago_initialize(const KeyframePoseGraph& graph,
                                                         const LagoOptions& options = {});

}  // namespace cairn::base
