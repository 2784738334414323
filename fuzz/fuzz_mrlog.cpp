// Cairn multi-robot logs (common/multirobot_log.h) as cairn_mrlog and the agent's log source read
// them: InputError naming the line, or a log.
#include <sstream>

#include "common/errors.h"
#include "common/multirobot_log.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    cairn::parse_multirobot_log(in, "fuzz.mrlog");
  } catch (const cairn::InputError&) {
  }
  return 0;
}
