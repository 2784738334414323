// CARMEN logs (common/carmen_log.h), plain or gzip, as cairn_slam and the benchmarks read them:
// a malformed log must end in InputError, never a crash, a hang or another exception.
#include "common/carmen_log.h"
#include "common/errors.h"
#include "fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = cairn::fuzz::write_input(data, size, "input.log");
  try {
    cairn::read_carmen_log(path);
  } catch (const cairn::InputError&) {
  }
  return 0;
}
