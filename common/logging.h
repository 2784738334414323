#pragma once
// The one logging facade (spdlog). Loggers are tagged with component and robot:
//   auto log = cairn::make_logger("agent", RobotId{1});   log->info("keyframe {}", seq);
// Hot loops use CAIRN_LOG_EVERY_N_SEC to stay rate-limited. Apps only: core/ never logs.
#include <spdlog/spdlog.h>

#include <chrono>
#include <memory>
#include <string>

#include "common/ids.h"

namespace cairn {

std::shared_ptr<spdlog::logger> make_logger(const std::string& component, RobotId robot = RobotId{});
/// Sets the level of every logger from a name ("debug", "info", "warn", ...).
void set_log_level(const std::string& level);

}  // namespace cairn

#define CAIRN_LOG_EVERY_N_SEC(logger, level, seconds, ...)                        \
  do {                                                                            \
    static std::chrono::steady_clock::time_point cairn_last_log_{};               \
    const auto cairn_now_ = std::chrono::steady_clock::now();                     \
    if (cairn_now_ - cairn_last_log_ >= std::chrono::duration<double>(seconds)) { \
      cairn_last_log_ = cairn_now_;                                               \
      (logger)->log(level, __VA_ARGS__);                                          \
    }                                                                             \
  } while (0)
