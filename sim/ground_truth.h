#pragma once
// Ground-truth export of a simulated mission, for the evaluation tools:
//   gt_robot<N>.csv  true trajectory of robot N (stamp_ns,x_m,y_m,yaw_rad; common/trajectory.h)
//   gt_objects.csv   id,class,shape,x_m,y_m,z_m,yaw_rad,size_x,size_y,size_z,r,g,b
//   gt_robots.csv    id,start_x,start_y,start_yaw (T_world_start of each robot's odom frame)
#include <string>

#include "sim/simulator.h"

namespace cairn::sim {

/// Writes the three kinds of files into `dir` (created if needed). Returns false on I/O errors.
bool write_ground_truth(const Simulator& sim, const std::string& dir);

}  // namespace cairn::sim
