// g2o pose graphs (common/g2o_io.h) as cairn_g2o_opt reads them, then the initial guess built from
// the edges (the first thing done with a loaded graph): InputError or a graph, nothing else.
#include "common/errors.h"
#include "common/g2o_io.h"
#include "fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = cairn::fuzz::write_input(data, size, "input.g2o");
  try {
    const cairn::G2oGraph graph = cairn::read_g2o(path);
    const auto poses = cairn::initialize_from_odometry(graph);
    cairn::g2o_chi2(graph, poses);
  } catch (const cairn::InputError&) {
  }
  return 0;
}
