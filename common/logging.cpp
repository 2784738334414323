#include "common/logging.h"

#include <spdlog/sinks/stdout_color_sinks.h>

namespace cairn {

std::shared_ptr<spdlog::logger> make_logger(const std::string& component, RobotId robot) {
  const std::string name = robot.valid() ? component + "/" + to_string(robot) : component;
  if (auto existing = spdlog::get(name)) return existing;
  auto logger = spdlog::stderr_color_mt(name);
  logger->set_pattern("[%H:%M:%S.%e] [%n] %^%l%$ %v");
  return logger;
}

void set_log_level(const std::string& level) { spdlog::set_level(spdlog::level::from_str(level)); }

}  // namespace cairn
