#include "base_station/console/command_api.h"

#include <cmath>
#include <cstdio>

namespace cairn::base {

bool operator_token_matches(const std::string& authorization, const std::string& token) {
  const std::string prefix = "Bearer ";
  if (token.empty() || authorization.size() != prefix.size() + token.size()) return false;
  if (authorization.compare(0, prefix.size(), prefix) != 0) return false;
  unsigned char diff = 0;
  for (size_t i = 0; i < token.size(); ++i) diff |= uint8_t(authorization[prefix.size() + i] ^ token[i]);
  return diff == 0;
}

namespace {

std::nullopt_t fail(std::string* error, const std::string& what) {
  *error = what;
  return std::nullopt;
}

}  // namespace

std::optional<CommandRequest> parse_command_request(const std::string& body, const std::vector<RobotId>& known_robots,
                                                    std::string* error) {
  const nlohmann::json j = nlohmann::json::parse(body, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return fail(error, "the body is not JSON");
  if (!j.is_object()) return fail(error, "the body must be a JSON object");
  if (!j.contains("kind") || !j["kind"].is_string())
    return fail(error, "\"kind\" is missing (goto, stop, resume, home)");
  CommandRequest r;
  const std::string kind = j["kind"];
  if (kind == "goto") {
    r.kind = CommandKind::kGoTo;
  } else if (kind == "stop") {
    r.kind = CommandKind::kStop;
  } else if (kind == "resume") {
    r.kind = CommandKind::kResume;
  } else if (kind == "home") {
    r.kind = CommandKind::kHome;
  } else {
    return fail(error, "unknown kind \"" + kind + "\" (goto, stop, resume, home)");
  }
  if (!j.contains("robot")) return fail(error, "\"robot\" is missing (a robot id or \"all\")");
  const nlohmann::json& robot = j["robot"];
  if (robot.is_string() && robot.get<std::string>() == "all") {
    r.robots = known_robots;
  } else if (robot.is_number_integer() && robot.get<int64_t>() >= 0 && robot.get<int64_t>() <= 1000) {
    r.robots = {RobotId(int(robot.get<int64_t>()))};
  } else {
    return fail(error, "\"robot\" must be a robot id (0..1000) or \"all\"");
  }
  if (r.kind == CommandKind::kGoTo) {
    for (const char* axis : {"x_m", "y_m"}) {
      // JSON has no NaN: a non-finite point arrives as null or a string and is named here.
      if (!j.contains(axis) || !j[axis].is_number()) {
        return fail(error, std::string("\"") + axis + "\" must be a number (metres, map frame) for goto");
      }
    }
    r.point_global_m = {j["x_m"].get<double>(), j["y_m"].get<double>()};
  }
  return r;
}

void CommandInbox::start_after(uint32_t last_seq) {
  std::lock_guard<std::mutex> lock(mutex_);
  next_seq_ = std::max(next_seq_, last_seq + 1);
}

std::vector<uint32_t> CommandInbox::push(const CommandRequest& request) {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<uint32_t> seqs;
  for (RobotId robot : request.robots) {
    seqs.push_back(next_seq_);
    entries_.push_back({next_seq_++, robot, request});
  }
  return seqs;
}

std::vector<CommandInbox::Entry> CommandInbox::take_all() {
  std::lock_guard<std::mutex> lock(mutex_);
  return std::exchange(entries_, {});
}

nlohmann::json commands_json(const std::vector<CommandRecord>& records, size_t max_entries) {
  nlohmann::json out = nlohmann::json::array();
  for (auto it = records.rbegin(); it != records.rend() && out.size() < max_entries; ++it) {
    nlohmann::json c = {{"seq", it->seq},
                        {"robot", it->robot.value},
                        {"kind", to_string(it->kind)},
                        {"sent_s", double(it->sent_ns) * 1e-9},
                        {"state", to_string(it->state)},
                        {"note", it->note}};
    if (it->kind == CommandKind::kGoTo) {
      c["x_m"] = it->point_global_m.x();
      c["y_m"] = it->point_global_m.y();
    }
    out.push_back(std::move(c));
  }
  return out;
}

}  // namespace cairn::base
