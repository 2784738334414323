#pragma once
// Runs a command line through /bin/sh for process-level tests; captures stdout+stderr.
#include <filesystem>
#include <string>

namespace cairn::test {

struct CommandResult {
  int exit_code = -1;
  std::string output;
};

CommandResult run_command(const std::string& command_line);
std::string bin(const std::string& name);  ///< path of a built executable
std::string source_path(const std::string& relative);

/// A cairn_mission run: its output folder and what it printed.
struct MissionRun {
  std::filesystem::path out;
  CommandResult result;
};
/// Runs cairn_mission on `world` (source-relative) into a fresh temporary folder named by `tag`.
MissionRun run_mission(const std::string& world, const std::string& tag, const std::string& extra_args = "");

}  // namespace cairn::test
