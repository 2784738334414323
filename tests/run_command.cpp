#include "run_command.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>

namespace cairn::test {

CommandResult run_command(const std::string& command_line) {
  CommandResult r;
  FILE* pipe = popen((command_line + " 2>&1").c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) r.output.append(buf.data(), n);
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return r;
}

std::string bin(const std::string& name) { return std::string(CAIRN_BIN_DIR) + "/" + name; }
std::string source_path(const std::string& relative) { return std::string(CAIRN_SOURCE_DIR) + "/" + relative; }

MissionRun run_mission(const std::string& world, const std::string& tag, const std::string& extra_args) {
  MissionRun m;
  m.out = std::filesystem::path(::testing::TempDir()) / (tag + "_" + std::to_string(getpid()));
  std::filesystem::remove_all(m.out);
  m.result = run_command(bin("cairn_mission") + " --world " + source_path(world) + " --out " + m.out.string() +
                         " --port 0 " + extra_args);
  return m;
}

}  // namespace cairn::test
