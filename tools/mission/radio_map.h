#pragma once
// A picture of the simulated radio (radio.png in a --radio-model mission's folder): the floor plan
// coloured by the power a robot would receive from the team's best antenna (sim/radio_model.h),
// the antennas, and each robot's true track, drawn thick where its link was cut.
#include <string>

#include "sim/world.h"

namespace cairn::mission {

/// `radio_csv`: what cairn_sim --radio wrote; `ground_truth_dir`: its gt_robot<N>.csv tracks.
/// False, with nothing written, when the PNG cannot be written.
bool write_radio_map(const sim::World& world, const std::string& radio_csv, const std::string& ground_truth_dir,
                     const std::string& png_path);

}  // namespace cairn::mission
