// World files (sim/world.h) as cairn_mission, cairn_sim and cairn_mrlog from-world read them, then
// two steps of the simulator on what loaded: a bad world must end in InputError naming the key,
// never a crash, an uncaught yaml-cpp exception or a simulation that never returns (the hangs of
// a huge dt_s or max_speed_mps that issue #21 found were values that loaded).
#include <filesystem>

#include "common/errors.h"
#include "fuzz/fuzz_input.h"
#include "sim/simulator.h"
#include "sim/world.h"

namespace {

// The floor plans the repository's worlds name, beside the fuzzed YAML (it names its image by a
// path relative to itself).
void link_floor_plans(const std::string& dir) {
  namespace fs = std::filesystem;
  for (const auto& entry : fs::directory_iterator(std::string(CAIRN_SOURCE_DIR) + "/worlds")) {
    if (entry.path().extension() != ".pgm") continue;
    std::error_code ec;
    fs::create_symlink(entry.path(), fs::path(dir) / entry.path().filename(), ec);
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  link_floor_plans(cairn::fuzz::scratch_dir());
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = cairn::fuzz::write_input(data, size, "world.yaml");
  try {
    cairn::sim::WorldFile file = cairn::sim::load_world_file(path);
    file.sim.enable_camera = false;  // the camera's rendering is not input decoding; it is slow
    cairn::sim::Simulator sim(file.world, file.sim);
    for (int i = 0; i < 2 && !sim.done(); ++i) sim.step();
  } catch (const cairn::InputError&) {
  }
  return 0;
}
