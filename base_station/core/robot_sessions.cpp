#include "base_station/core/robot_sessions.h"

#include <nlohmann/json.hpp>

#include <stdexcept>

namespace cairn::base {

RobotId RobotSessions::resolve(RobotId robot, uint32_t session, bool* is_new) {
  if (!robot.valid() || robot.value >= kFirstRestartId)
    throw std::invalid_argument("RobotSessions: robot id " + std::to_string(robot.value) + " out of range");
  if (is_new) *is_new = false;
  int ordinal = 0;
  for (const auto& [base_id, s] : by_base_id_) {
    if (s.robot != robot) continue;
    if (s.session == session) return base_id;
    ++ordinal;
  }
  const RobotId base_id = ordinal == 0 ? robot : RobotId(next_restart_id_++);
  by_base_id_[base_id] = RobotSession{base_id, robot, session, ordinal + 1};
  current_[robot] = base_id;
  if (is_new) *is_new = true;
  return base_id;
}

bool RobotSessions::restore(const RobotSession& s) {
  if (!s.robot.valid() || s.robot.value >= kFirstRestartId || s.ordinal < 1) return false;
  if ((s.ordinal == 1) != (s.base_id == s.robot)) return false;
  if (s.ordinal > 1 && s.base_id.value < kFirstRestartId) return false;
  const auto known = by_base_id_.find(s.base_id);
  if (known != by_base_id_.end())
    return known->second.robot == s.robot && known->second.session == s.session && known->second.ordinal == s.ordinal;
  for (const auto& [base_id, other] : by_base_id_) {
    if (other.robot == s.robot && (other.session == s.session || other.ordinal == s.ordinal)) return false;
  }
  by_base_id_[s.base_id] = s;
  const auto cur = current_.find(s.robot);
  if (cur == current_.end() || by_base_id_.at(cur->second).ordinal < s.ordinal) current_[s.robot] = s.base_id;
  if (s.base_id.value >= next_restart_id_) next_restart_id_ = s.base_id.value + 1;
  return true;
}

std::optional<RobotSession> RobotSessions::find(RobotId base_id) const {
  const auto it = by_base_id_.find(base_id);
  if (it == by_base_id_.end()) return std::nullopt;
  return it->second;
}

bool RobotSessions::is_current(RobotId base_id) const {
  const auto s = find(base_id);
  return !s || current_.at(s->robot) == base_id;
}

RobotId RobotSessions::current(RobotId robot) const {
  const auto it = current_.find(robot);
  return it == current_.end() ? robot : it->second;
}

std::string RobotSessions::label(RobotId base_id) const {
  const auto s = find(base_id);
  if (!s || s->ordinal == 1) return to_string(s ? s->robot : base_id);
  return to_string(s->robot) + " session " + std::to_string(s->ordinal);
}

std::vector<RobotSession> RobotSessions::restarts() const {
  std::vector<RobotSession> out;
  for (const auto& [base_id, s] : by_base_id_)
    if (s.ordinal > 1) out.push_back(s);
  return out;
}

std::string session_record_to_json(const RobotSession& s) {
  return nlohmann::json{
      {"base_id", s.base_id.value}, {"robot", s.robot.value}, {"session", s.session}, {"ordinal", s.ordinal}}
      .dump();
}

std::optional<RobotSession> session_record_from_json(const std::string& text, std::string* error) {
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (!j.is_object()) {
    *error = "robot session record: not a JSON object";
    return std::nullopt;
  }
  for (const char* key : {"base_id", "robot", "session", "ordinal"}) {
    if (!j.contains(key) || !j[key].is_number_unsigned() || j[key].get<uint64_t>() > UINT32_MAX) {
      *error = std::string("robot session record: \"") + key + "\" is missing or not an integer in [0, 2^32)";
      return std::nullopt;
    }
  }
  if (j["base_id"].get<uint64_t>() > INT32_MAX || j["robot"].get<uint64_t>() >= RobotSessions::kFirstRestartId ||
      j["ordinal"].get<uint64_t>() < 1 || j["ordinal"].get<uint64_t>() > INT32_MAX) {
    *error = "robot session record: \"base_id\", \"robot\" or \"ordinal\" out of range";
    return std::nullopt;
  }
  return RobotSession{RobotId(j["base_id"].get<int32_t>()), RobotId(j["robot"].get<int32_t>()),
                      j["session"].get<uint32_t>(), j["ordinal"].get<int>()};
}

}  // namespace cairn::base
