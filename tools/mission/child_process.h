#pragma once
// A child process with its output in a log file; reaped with its peak memory (ru_maxrss) and CPU time.
#include <sys/types.h>

#include <string>
#include <vector>

namespace cairn::mission {

class ChildProcess {
 public:
  /// Starts argv[0] (a path) with stdout and stderr appended to `log_path`. Check started().
  ChildProcess(std::string name, const std::vector<std::string>& argv, const std::string& log_path);
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  bool started() const { return pid_ > 0; }
  pid_t pid() const { return pid_; }
  /// Non-blocking: true once the process has exited (then exit_code() and peak_rss_kb() are set).
  bool poll();
  void terminate();  ///< SIGTERM
  void kill();       ///< SIGKILL
  const std::string& name() const { return name_; }
  const std::string& log_path() const { return log_path_; }
  int exit_code() const { return exit_code_; }  ///< 128+signal when killed by a signal
  long peak_rss_kb() const { return peak_rss_kb_; }
  double cpu_s() const { return cpu_s_; }  ///< user + system CPU seconds, once exited
  bool exited() const { return exited_; }

 private:
  std::string name_;
  std::string log_path_;
  pid_t pid_ = -1;
  bool exited_ = false;
  int exit_code_ = -1;
  long peak_rss_kb_ = 0;
  double cpu_s_ = 0.0;
};

}  // namespace cairn::mission
