#pragma once
// Runs a command line through /bin/sh for process-level tests; captures stdout+stderr.
#include <string>

namespace cairn::test {

struct CommandResult {
  int exit_code = -1;
  std::string output;
};

CommandResult run_command(const std::string& command_line);
std::string bin(const std::string& name);  ///< path of a built executable
std::string source_path(const std::string& relative);

}  // namespace cairn::test
