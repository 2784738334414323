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

std::string command_record_to_json(const CommandRecord& r) {
  return nlohmann::json{{"seq", r.seq},
                        {"robot", r.robot.value},
                        {"kind", int(r.kind)},
                        {"kind_name", to_string(r.kind)},  // for a person reading the journal
                        {"local_m", {r.point_local_m.x(), r.point_local_m.y()}},
                        {"global_m", {r.point_global_m.x(), r.point_global_m.y()}},
                        {"sent_ns", r.sent_ns}}
      .dump();
}

std::optional<CommandRecord> command_record_from_json(const std::string& text, std::string* error) {
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (!j.is_object()) return fail(error, "an operator command record must be a JSON object");
  const auto integer = [&](const char* key, int64_t lo, int64_t hi) -> std::optional<int64_t> {
    if (!j.contains(key) || !j[key].is_number_integer()) return std::nullopt;
    const int64_t v = j[key].get<int64_t>();
    return v >= lo && v <= hi ? std::optional<int64_t>(v) : std::nullopt;
  };
  const auto point = [&](const char* key) -> std::optional<Eigen::Vector2d> {
    if (!j.contains(key) || !j[key].is_array() || j[key].size() != 2 || !j[key][0].is_number() ||
        !j[key][1].is_number())
      return std::nullopt;
    const Eigen::Vector2d p(j[key][0].get<double>(), j[key][1].get<double>());
    return p.allFinite() ? std::optional<Eigen::Vector2d>(p) : std::nullopt;
  };
  const auto seq = integer("seq", 1, UINT32_MAX);
  const auto robot = integer("robot", 0, 1000);
  const auto kind_value = integer("kind", 0, 255);
  const auto kind = kind_value ? command_kind_from(uint8_t(*kind_value)) : std::nullopt;
  const auto sent_ns = integer("sent_ns", 0, INT64_MAX);
  const auto local = point("local_m");
  const auto global = point("global_m");
  if (!seq) return fail(error, "operator command record: \"seq\" must be 1..4294967295");
  if (!robot) return fail(error, "operator command record: \"robot\" must be 0..1000");
  if (!kind) return fail(error, "operator command record: unknown \"kind\"");
  if (!sent_ns) return fail(error, "operator command record: \"sent_ns\" must be a time in ns");
  if (!local || !global) return fail(error, "operator command record: \"local_m\" and \"global_m\" must be [x, y]");
  CommandRecord r;
  r.seq = uint32_t(*seq);
  r.robot = RobotId(int(*robot));
  r.kind = *kind;
  r.point_local_m = *local;
  r.point_global_m = *global;
  r.sent_ns = *sent_ns;
  return r;
}

void CommandInbox::push_verdict(const VerdictRequest& request) {
  std::lock_guard<std::mutex> lock(mutex_);
  verdicts_.push_back(request);
}

std::vector<VerdictRequest> CommandInbox::take_verdicts() {
  std::lock_guard<std::mutex> lock(mutex_);
  return std::exchange(verdicts_, {});
}

void CommandInbox::push_alignment(const AlignmentRequest& request) {
  std::lock_guard<std::mutex> lock(mutex_);
  alignments_.push_back(request);
}

std::vector<AlignmentRequest> CommandInbox::take_alignments() {
  std::lock_guard<std::mutex> lock(mutex_);
  return std::exchange(alignments_, {});
}

void CommandInbox::ack_alert(const std::string& key) {
  std::lock_guard<std::mutex> lock(mutex_);
  acked_alerts_.insert(key);
}

std::set<std::string> CommandInbox::acked_alerts() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return acked_alerts_;
}

void CommandInbox::push_search(const SearchControlRequest& request) {
  std::lock_guard<std::mutex> lock(mutex_);
  search_requests_.push_back(request);
}

std::vector<SearchControlRequest> CommandInbox::take_search() {
  std::lock_guard<std::mutex> lock(mutex_);
  return std::exchange(search_requests_, {});
}

void CommandInbox::post_search(const SearchControls& controls) {
  std::lock_guard<std::mutex> lock(mutex_);
  search_ = controls;
  ++generation_;
}

SearchControls CommandInbox::search() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return search_;
}

void CommandInbox::post_states(nlohmann::json states) {
  std::lock_guard<std::mutex> lock(mutex_);
  states_ = std::move(states);
  ++generation_;
}

uint64_t CommandInbox::generation() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return generation_;
}

nlohmann::json CommandInbox::states() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return states_;
}

namespace {

std::optional<ObjectVerdict> verdict_from(const std::string& name) {
  for (ObjectVerdict v : {ObjectVerdict::kUnreviewed, ObjectVerdict::kConfirmed, ObjectVerdict::kFalse}) {
    if (name == to_string(v)) return v;
  }
  return std::nullopt;
}

constexpr size_t kMaxNoteChars = 200;

}  // namespace

std::optional<VerdictRequest> parse_verdict_request(ObjectId object, const std::string& body, std::string* error) {
  const nlohmann::json j = nlohmann::json::parse(body, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return fail(error, "the body is not JSON");
  if (!j.is_object()) return fail(error, "the body must be a JSON object");
  if (!j.contains("verdict") || !j["verdict"].is_string())
    return fail(error, "\"verdict\" is missing (confirmed, false, unreviewed)");
  const auto verdict = verdict_from(j["verdict"].get<std::string>());
  if (!verdict)
    return fail(error, "unknown verdict \"" + j["verdict"].get<std::string>() + "\" (confirmed, false, unreviewed)");
  VerdictRequest r{object, *verdict, ""};
  if (j.contains("note")) {
    if (!j["note"].is_string()) return fail(error, "\"note\" must be text");
    r.note = j["note"].get<std::string>();
    if (r.note.size() > kMaxNoteChars) return fail(error, "\"note\" is longer than 200 characters");
  }
  return r;
}

std::optional<AlignmentRequest> parse_alignment_request(RobotId robot, const std::string& body, std::string* error) {
  const nlohmann::json j = nlohmann::json::parse(body, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return fail(error, "the body is not JSON");
  if (!j.is_object()) return fail(error, "the body must be a JSON object");
  double v[3];
  const char* keys[3] = {"x_m", "y_m", "yaw_deg"};
  for (int i = 0; i < 3; ++i) {
    // JSON has no NaN: a non-finite value arrives as null or a string and is named here.
    if (!j.contains(keys[i]) || !j[keys[i]].is_number())
      return fail(error,
                  std::string("\"") + keys[i] + "\" must be a number (the robot's entry on the map, and its heading)");
    v[i] = j[keys[i]].get<double>();
    if (!std::isfinite(v[i]) || std::abs(v[i]) > 1e4)
      return fail(error, std::string("\"") + keys[i] + "\" is out of range");
  }
  return AlignmentRequest{robot, SE2(v[0], v[1], v[2] * M_PI / 180.0)};
}

std::string alignment_request_to_json(const AlignmentRequest& r) {
  return nlohmann::json{{"robot", r.robot.value},
                        {"x_m", r.T_global_local.x()},
                        {"y_m", r.T_global_local.y()},
                        {"yaw_deg", r.T_global_local.yaw() * 180.0 / M_PI}}
      .dump();
}

std::optional<AlignmentRequest> alignment_request_from_json(const std::string& text, std::string* error) {
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (!j.is_object() || !j.contains("robot") || !j["robot"].is_number_integer() || j["robot"].get<int64_t>() < 0 ||
      j["robot"].get<int64_t>() > 1000)
    return fail(error, "an alignment record must be a JSON object with a robot id");
  return parse_alignment_request(RobotId(j["robot"].get<int32_t>()), text, error);
}

std::string verdict_record_to_json(const VerdictRecord& r) {
  return nlohmann::json{{"robot", r.object.robot.value},
                        {"seq", r.object.seq},
                        {"verdict", to_string(r.verdict)},
                        {"note", r.note},
                        {"at_ns", r.at_ns}}
      .dump();
}

std::optional<VerdictRecord> verdict_record_from_json(const std::string& text, std::string* error) {
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (!j.is_object()) return fail(error, "a verdict record must be a JSON object");
  const bool ids = j.contains("robot") && j["robot"].is_number_integer() && j.contains("seq") &&
                   j["seq"].is_number_integer() && j["robot"].get<int64_t>() >= 0 && j["seq"].get<int64_t>() >= 0;
  if (!ids) return fail(error, "verdict record: \"robot\" and \"seq\" must be object ids");
  const auto verdict = j.contains("verdict") && j["verdict"].is_string() ? verdict_from(j["verdict"]) : std::nullopt;
  if (!verdict) return fail(error, "verdict record: unknown \"verdict\"");
  if (!j.contains("note") || !j["note"].is_string()) return fail(error, "verdict record: \"note\" must be text");
  if (!j.contains("at_ns") || !j["at_ns"].is_number_integer()) return fail(error, "verdict record: \"at_ns\" missing");
  return VerdictRecord{ObjectId{RobotId(int(j["robot"].get<int64_t>())), int32_t(j["seq"].get<int64_t>())}, *verdict,
                       j["note"].get<std::string>(), j["at_ns"].get<int64_t>()};
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
