#pragma once
// The console's command endpoint, apart from HTTP: who may command (the operator token), what a
// request says (JSON -> CommandRequest, every fault named), and the inbox that hands accepted
// requests from the HTTP threads to the base's thread with their sequence numbers.
//   POST /api/commands  {"robot": 1 | "all", "kind": "goto"|"stop"|"resume"|"home", "x_m": .., "y_m": ..}
//   with "Authorization: Bearer <token>"; the point is in the merged map's frame (goto only).
// Also the operator's object verdicts and alignments of unlinked robots' maps (below).
#include <cstdint>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "base_station/core/object_verdicts.h"
#include "base_station/core/operator_commands.h"
#include "base_station/core/search_controls.h"

namespace cairn::base {

/// True when `authorization` (the request's Authorization header) is "Bearer <token>". Compares in
/// time independent of where the strings differ; an empty token never matches.
bool operator_token_matches(const std::string& authorization, const std::string& token);

/// Parses a request body. "all" goes to every robot in `known_robots`. nullopt with `error` naming
/// the field for bad JSON, a missing or unknown kind, a robot that is not a number or "all", or a
/// goto without numeric x_m and y_m. (Whether the robot exists or the point is on the map is
/// check_command()'s decision.)
std::optional<CommandRequest> parse_command_request(const std::string& body, const std::vector<RobotId>& known_robots,
                                                    std::string* error);

/// A verdict request: POST /api/objects/<robot>-<seq>/verdict {"verdict": "confirmed" | "false" |
/// "unreviewed", "note": "..."} (note optional, at most 200 characters). nullopt with `error` naming
/// the fault. (Whether the object exists is the server's check, against the newest snapshot.)
struct VerdictRequest {
  ObjectId object;
  ObjectVerdict verdict = ObjectVerdict::kUnreviewed;
  std::string note;
};
std::optional<VerdictRequest> parse_verdict_request(ObjectId object, const std::string& body, std::string* error);

/// The operator's alignment of an unlinked robot's own map over the global map: POST
/// /api/robots/<id>/align {"x_m": .., "y_m": .., "yaw_deg": ..}, where the robot's entry (its local
/// origin) goes on the map and which way its local x points. nullopt with `error` naming the field
/// (missing, not a number, or beyond 10 km). (Whether the robot is unlinked is the server's check.)
struct AlignmentRequest {
  RobotId robot;
  SE2 T_global_local;
};
std::optional<AlignmentRequest> parse_alignment_request(RobotId robot, const std::string& body, std::string* error);
/// An alignment as the base journals it (the same JSON plus "robot"), and back.
std::string alignment_request_to_json(const AlignmentRequest& request);
std::optional<AlignmentRequest> alignment_request_from_json(const std::string& text, std::string* error);

/// A verdict as the base journals it (JSON), and back; from: nullopt with `error` naming the fault.
std::string verdict_record_to_json(const VerdictRecord& record);
std::optional<VerdictRecord> verdict_record_from_json(const std::string& text, std::string* error);

/// The desk between the console's HTTP threads and the base's thread, both ways: accepted requests
/// wait here for the base (sequence numbers are given here, one per robot a request goes to, so the
/// console can answer with them at once), and the base posts every command's newest state here the
/// moment it changes (not with the next console snapshot, a second later). Thread-safe.
class CommandInbox {
 public:
  struct Entry {
    uint32_t seq = 0;
    RobotId robot;
    CommandRequest request;
  };
  /// Sequence numbers continue after `last_seq` (the journal's newest, after a restart).
  void start_after(uint32_t last_seq);
  std::vector<uint32_t> push(const CommandRequest& request);
  std::vector<Entry> take_all();
  void push_verdict(const VerdictRequest& request);
  void push_alignment(const AlignmentRequest& request);
  std::vector<AlignmentRequest> take_alignments();
  /// An operator acknowledged the alert `key` (AlertLog keys); kept for the rest of the mission.
  void ack_alert(const std::string& key);
  std::set<std::string> acked_alerts() const;
  std::vector<VerdictRequest> take_verdicts();
  /// The commands and their states (commands_json), as the base last posted them.
  void post_states(nlohmann::json states);
  nlohmann::json states() const;
  /// How many times states or search controls were posted (the console's event stream watches it).
  uint64_t generation() const;
  /// The operator's search controls (search_api.h), for the base's thread.
  void push_search(const SearchControlRequest& request);
  std::vector<SearchControlRequest> take_search();
  /// The search controls as the base last posted them (a new request is checked against them).
  void post_search(const SearchControls& controls);
  SearchControls search() const;

 private:
  mutable std::mutex mutex_;
  nlohmann::json states_ = nlohmann::json::array();
  uint64_t generation_ = 0;
  uint32_t next_seq_ = 1;
  std::vector<Entry> entries_;
  std::vector<VerdictRequest> verdicts_;
  std::vector<AlignmentRequest> alignments_;
  std::vector<SearchControlRequest> search_requests_;
  SearchControls search_;
  std::set<std::string> acked_alerts_;
};

/// One sent command as the base journals it (JSON: seq, robot, kind, both points, sent_ns), and
/// back. from: nullopt with `error` naming what is wrong for anything that is not such a record.
std::string command_record_to_json(const CommandRecord& record);
std::optional<CommandRecord> command_record_from_json(const std::string& text, std::string* error);

/// The console's list of commands, newest first: seq, robot, kind, x_m, y_m, sent_s, state, note.
nlohmann::json commands_json(const std::vector<CommandRecord>& records, size_t max_entries = 50);

}  // namespace cairn::base
