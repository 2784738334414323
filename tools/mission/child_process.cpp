#include "tools/mission/child_process.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>

extern char** environ;

namespace cairn::mission {

ChildProcess::ChildProcess(std::string name, const std::vector<std::string>& argv, const std::string& log_path)
    : name_(std::move(name)), log_path_(log_path) {
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  pid_t pid = -1;
  if (posix_spawn(&pid, args[0], &actions, nullptr, args.data(), environ) == 0) pid_ = pid;
  posix_spawn_file_actions_destroy(&actions);
}

ChildProcess::~ChildProcess() {
  if (started() && !exited_) {
    kill();
    int status = 0;
    waitpid(pid_, &status, 0);
  }
}

bool ChildProcess::poll() {
  if (!started() || exited_) return exited_ || !started();
  int status = 0;
  struct rusage usage {};
  const pid_t r = wait4(pid_, &status, WNOHANG, &usage);
  if (r != pid_) return false;
  exited_ = true;
  peak_rss_kb_ = usage.ru_maxrss;
  cpu_s_ = double(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
           1e-6 * double(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
  exit_code_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return true;
}

void ChildProcess::terminate() {
  if (started() && !exited_) ::kill(pid_, SIGTERM);
}

void ChildProcess::kill() {
  if (started() && !exited_) ::kill(pid_, SIGKILL);
}

}  // namespace cairn::mission
