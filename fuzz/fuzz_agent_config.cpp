// The agent's YAML config (robot_agent/app/agent_config.h, cairn_agent --config): InputError naming
// the key, or options.
#include "common/errors.h"
#include "fuzz/fuzz_input.h"
#include "robot_agent/app/agent_config.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = cairn::fuzz::write_input(data, size, "agent.yaml");
  try {
    cairn::agent::load_agent_options(path);
  } catch (const cairn::InputError&) {
  }
  return 0;
}
