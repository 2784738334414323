#pragma once
// Options of the base station's MultiRobotMapper, with defaults that suit the simulator and
// indoor rescue scenes.
#include "base_station/core/loop_closer.h"
#include "base_station/core/pcm.h"
#include "base_station/core/pose_graph_2d.h"
#include "common/occupancy_grid.h"

namespace cairn::base {

struct MapperOptions {
  OccupancyGridOptions grid;                ///< global map; resolution 0.05 m by default
  /// Max-range beams (no return) clear free space up to min(scan range_max, this).
  double no_return_clear_range_m = 10.0;

  PoseGraphOptions graph;                   ///< robust losses per edge kind (Cauchy on loops)
  PoseGraphSolveOptions solve;
  /// Prior pinning each linked robot's first keyframe at T_global_local * T_local_base(first).
  double start_prior_sigma_xy_m = 0.01;
  double start_prior_sigma_yaw_rad = 0.005;
  /// When a keyframe's predecessor (seq-1) has not arrived, it is linked to the nearest earlier
  /// keyframe by the difference of their local poses, with this uncertainty per missing step.
  double gap_sigma_xy_m_per_step = 0.05;
  double gap_sigma_yaw_rad_per_step = 0.02;

  /// Automatic merging: place recognition + verification (loop_closer.h), PCM on each robot
  /// pair's inter-robot closures before the pair is first linked (pcm.h).
  bool detect_loops = true;
  LoopCloserOptions loop_closer;
  PcmOptions pcm;
  /// Mutually consistent inter-robot closures needed to link two robots for the first time.
  int min_link_clique = 3;
  /// Max Ceres iterations of an incremental update (warm-started); a full re-solve with LAGO
  /// initialisation (solve.max_iterations) runs when robots are first linked.
  int incremental_max_iterations = 10;

  /// Reports of the same class whose global centroids are this close are one object.
  double merge_distance_m = 0.75;
  /// Voxel size of the merged object clouds (global frame).
  double object_voxel_m = 0.02;
};

}  // namespace cairn::base
