#include "run_command.h"

#include <sys/wait.h>

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

}  // namespace cairn::test
