#pragma once
// What the navigation core asks of the robot's base: a unicycle velocity in the robot's frame.

namespace cairn::agent {

struct VelocityCommand {
  double linear_mps = 0;     ///< forward speed (never negative: the robot does not reverse blind)
  double angular_radps = 0;  ///< counter-clockwise
};

}  // namespace cairn::agent
