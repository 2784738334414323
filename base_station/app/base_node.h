#pragma once
// The base station's DDS side around MultiRobotMapper: keyframe/object/status readers in;
// ack/correction writers out; a console snapshot refreshed for the HTTP thread; exports at the end.
// Data flow: keyframe/object topics -> dds::from_msg -> MultiRobotMapper -> journal (SQLite) ->
//            optimize -> ack + correction topics; plan_exploration -> goal topic; console
//            snapshot; export_all(). Console POST /api/commands -> CommandInbox -> CommandBook ->
//            journal -> operator_command topic; robots' statuses -> CommandBook.
// A sample is acknowledged only once it is in the journal; a restarted base resumes from it.
#include <atomic>
#include <chrono>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "base_station/app/ros2_output.h"
#include "base_station/console/alert_log.h"
#include "base_station/console/console_server.h"
#include "base_station/console/snapshot.h"
#include "base_station/core/active_linking.h"
#include "base_station/core/exploration.h"
#include "base_station/core/goal_allocator.h"
#include "base_station/core/keep_out_relay.h"
#include "base_station/core/multi_robot_mapper.h"
#include "base_station/core/object_verdicts.h"
#include "base_station/core/operator_commands.h"
#include "base_station/core/robot_sessions.h"
#include "base_station/core/round_trip.h"
#include "base_station/core/saliency_layer.h"
#include "base_station/store/journal.h"
#include "cairn_msgsPubSubTypes.h"
#include "common/logging.h"
#include "dds/endpoints.h"

namespace cairn::base {

struct BaseNodeOptions {
  int domain_id = 0;
  std::vector<std::string> peers;  ///< unicast discovery peers (IPv4): the robots
  bool use_shared_memory = true;   ///< false: UDP only, even to processes on this host
  bool slow_link = false;          ///< the robots are behind a slow radio: announce less often
  std::string security_dir;        ///< DDS Security identity (dds::ParticipantOptions); empty = off
  std::string out_dir = "out";
  int expected_robots = 0;              ///< finish once this many robots reported "finished"; 0 = run until stopped
  std::map<RobotId, SE2> robot_starts;  ///< known start poses (until cross-robot merging lands)
  std::map<RobotId, EntryHint> entry_hints;  ///< roughly where robots entered (MultiRobotMapper::set_entry_hint)
  double optimize_period_s = 1.0;
  /// A keyframe shows in the console at most this long after it arrived (a quick snapshot between
  /// optimise ticks; the page's update latency, docs/benchmarks.md).
  double console_update_s = 0.2;
  double exploration_period_s = 2.0;    ///< how often the exploration goals are planned anew (when the map changed)
  ExplorationOptions exploration;       ///< how goals are chosen (coordination, victims' pull, ...)
  ActiveLinkingOptions active_linking;  ///< when and how robots not placed yet are sent to meet a teammate
  SaliencyLayerOptions saliency;        ///< the saliency layer the planner weights frontiers by
  ConsoleOptions console;
  bool serve_after_finish = false;  ///< keep the console up after the mission ended
  std::string journal_path;         ///< default <out_dir>/journal.sqlite
  std::string operator_token;       ///< the console's commands need it; empty = commands off
  bool new_mission = false;         ///< move an existing journal aside instead of resuming it
  bool ros2 = false;                ///< the map, frames, paths and objects as ROS 2 topics (Ros2Output)
};

class BaseNode {
 public:
  static std::unique_ptr<BaseNode> create(const BaseNodeOptions& options, const MapperOptions& mapper_options,
                                          std::string* error);
  /// Runs until every expected robot finished (or stop() is called); exports; returns an exit code.
  int run();
  void stop() { stop_ = true; }
  int console_port() const { return console_ ? console_->port() : -1; }

 private:
  struct RobotLink {
    cairn_msgs::RobotStatus last_status;
    bool has_status = false;
    double last_heard_s = -1;  ///< wall seconds since start
    int bad_samples = 0;
    int keyframe_pose_updates = 0;  ///< the agent's loop-closed keyframe poses, stored
    RoundTrip round_trip;           ///< the radio link's round trip (live statuses only)
  };
  BaseNode(const BaseNodeOptions& options, const MapperOptions& mapper_options);
  bool open_journal(std::string* error);
  void restore(const JournalContents& contents);
  // One sample into the mapper (validated by dds::from_msg); a bad one is counted and logged.
  AddResult ingest(const cairn_msgs::Keyframe& m);
  AddResult ingest(const cairn_msgs::KeyframePoses& m);
  AddResult ingest(const cairn_msgs::ObjectReport& m);
  /// The status's robot (its session's base id), or nullopt when refused. `news`: its first status,
  /// or "finished" changed.
  std::optional<RobotId> ingest(const cairn_msgs::RobotStatus& m, bool live, bool* news = nullptr);
  /// dds::from_msg (which validates), the sample's robot set to its session's base id (`*robot`),
  /// then `add` on it; kRejected with the reason when either refuses it (ingest's common part).
  template <typename Msg, typename Add>
  AddResult convert_and_add(const Msg& m, std::optional<RobotId>* robot, Add&& add);
  /// The base's id for a sample's robot and session (RobotSessions); a new session is journaled and
  /// a restart logged. nullopt for a robot id out of range.
  std::optional<RobotId> base_id(int32_t robot_id, uint32_t session);
  /// Addresses a message to `robot`'s session on the wire (robot id and session id); false for a
  /// session that ended (the robot runs a newer one): nothing is sent to it.
  template <typename Msg>
  bool address(RobotId robot, Msg* m) const {
    const auto s = sessions_.find(robot);
    m->robot_id(s ? s->robot.value : robot.value);
    m->session(s ? s->session : 0u);
    return sessions_.is_current(robot);
  }
  void count_rejected(int32_t robot_id);
  /// With DDS Security: true when `writer` holds robot `robot_id`'s certificate (dds/identity.h);
  /// a sample from anyone else (a team member speaking for another robot) is counted and logged.
  bool from_its_robot(const dds::GuidPrefix& writer, int32_t robot_id, const char* what);
  /// Counts and logs a sample refused because it would overwrite a stored one (AddStatus::kConflict).
  void count_refused(const AddResult& r, RobotId robot, const char* what);
  void journal(JournalKind kind, int32_t robot_id, int64_t key, std::vector<uint8_t> payload);
  void flush_journal();
  bool poll_inputs();
  void publish_acks_and_corrections();
  /// The operator's keep-out areas, in `r`'s own frame, when it must be told them (KeepOutRelay).
  void send_keep_out(const RobotSummary& r);
  // Exploration (base_node_exploration.cpp): the robots' navigation states in, goals out.
  void note_navigation(const NavStatus& nav, RobotId robot, bool live);
  /// `send`: false plans only (the final map's "where to search next"), no orders go out.
  void plan_and_publish_goals(bool send = true);
  void add_navigation_json(RobotId robot, nlohmann::json* link) const;
  /// Active linking: the meetings to drive now (kMeet goals by robot, placed or not); `placed_m` the
  /// placed robots the planner may send. `send`: false decides nothing (no orders go out).
  std::map<RobotId, MeetGoal> plan_meetings(const MergedMap& merged,
                                            const std::map<RobotId, std::optional<SE2>>& placements,
                                            const std::map<RobotId, Eigen::Vector2d>& placed_m, bool send);
  void report_meeting(const MeetingEvent& event, bool live);
  /// Explored area, open frontier and victims at the newest mission time (summary, console).
  void record_coverage(const MergedMap& merged);
  // What the console sees (base_node_console.cpp): the links, the snapshot, keyframe arrival times.
  /// `full`: with the map images (every optimise tick); quick: the last images kept.
  void refresh_snapshot(bool full = true);
  void note_keyframe_arrival();
  // Operator commands (base_node_commands.cpp): console inbox -> CommandBook, journal, DDS.
  void send_operator_commands();
  bool restore_command(const JournalRecord& r, std::string* error);
  bool restore_search(const JournalRecord& r, std::string* error);
  /// The operator's alert acknowledgements not journaled yet go into the journal (kAlertAck).
  void journal_alert_acks();
  bool restore_alert_ack(const JournalRecord& r, std::string* error);
  /// The operator's alignments of unlinked robots: to the mapper (judged at its next optimise) and
  /// the journal. True when there were any.
  bool take_alignments();
  bool restore_alignment(const JournalRecord& r, std::string* error);
  void apply_search_controls();  ///< the operator's pause, resume and keep-out areas
  bool restore_verdict(const JournalRecord& r, std::string* error);
  /// The merged map with the operator's verdicts on its objects (what the console and exports show).
  MergedMap judged_map() const;
  void after_restore_commands();
  void note_command_report(RobotId robot, const CommandReport& report, bool live);
  CommandCheckContext command_context(const MergedMap& merged) const;
  void report_linking(const OptimizeResult& result);
  nlohmann::json link_stats() const;
  bool all_finished() const;
  /// The results, then (--serve) the console until stopped, writing them again after an operator's
  /// alignment; the exit code.
  int finish();
  /// The final optimisation, the exports and summary.json; 0, or 4 / 5 when they could not be written.
  int write_results();
  double now_s() const;

  BaseNodeOptions options_;
  MapperOptions mapper_options_;
  MultiRobotMapper mapper_;
  std::shared_ptr<spdlog::logger> log_;
  std::unique_ptr<dds::Participant> participant_;
  std::unique_ptr<dds::Reader<dds::KeyframeTopic>> keyframe_in_;
  std::unique_ptr<dds::Reader<dds::ObjectTopic>> object_in_;
  std::unique_ptr<dds::Reader<dds::StatusTopic>> status_in_;
  std::unique_ptr<dds::Reader<dds::KeyframePosesTopic>> keyframe_poses_in_;
  std::unique_ptr<dds::Writer<dds::AckTopic>> ack_out_;
  struct EndedSessionAck {
    int32_t keyframe_seq = -1;
    int32_t objects = 0;
    double written_s = 0;  ///< now_s() when written
  };
  std::map<RobotId, EndedSessionAck> ended_session_acks_;  ///< the newest ack written to each ended session
  std::unique_ptr<Ros2Output> ros2_out_;                   ///< with --ros2
  void publish_ros2();
  std::unique_ptr<dds::Writer<dds::CorrectionTopic>> correction_out_;
  std::unique_ptr<dds::Writer<dds::GoalTopic>> goal_out_;
  std::unique_ptr<dds::Writer<dds::OperatorCommandTopic>> command_out_;
  std::unique_ptr<dds::Writer<dds::KeepOutTopic>> keep_out_out_;
  CommandInbox inbox_;           ///< commands the console accepted, for this thread (before console_: it points here)
  CommandBook commands_;         ///< every operator command sent and what became of it
  SearchControls search_;        ///< the operator's pause and keep-out areas (the planner obeys them)
  KeepOutRelay keep_out_relay_;  ///< which robot must be told the keep-out areas, in its own frame
  AlertLog alert_log_;           ///< every alert raised, first seen, acknowledged
  std::set<std::string> journaled_alert_acks_;  ///< acknowledgements in the journal (restored or written)
  int64_t last_alert_ack_key_ = 0;              ///< their journal keys: 1, 2, ...
  int64_t last_object_id_key_ = 0;              ///< journal keys of the object-id facts: 1, 2, ...
  ObjectVerdicts verdicts_;  ///< the operator's verdicts on objects (applied to every merged map shown)
  std::unique_ptr<ConsoleServer> console_;
  std::unique_ptr<Journal> journal_;
  ExplorationPlan plan_;                     ///< the newest exploration plan (console, goal topic, final export)
  GoalAllocator goals_;                      ///< each robot's order, the blacklist of failed goals
  ActiveLinker meetings_;                    ///< robots not placed yet sent to meet a placed teammate
  std::map<RobotId, NavStatus> navigation_;  ///< each robot's newest navigation state
  nlohmann::json coverage_series_ = nlohmann::json::array();  ///< [{t_s, free_m2, known_m2, frontier_m, victims}]
  uint64_t planned_version_ = 0;                              ///< mapper_.version() plan_ was made for
  bool replan_now_ = false;                 ///< a robot's order ended: plan without waiting for the period
  std::vector<JournalRecord> unjournaled_;  ///< stored in the mapper, not yet in the journal: no ack
  std::map<RobotId, cairn_msgs::RobotStatus> unjournaled_status_;  ///< newest status per robot, not yet journaled
  bool status_urgent_ = false;  ///< a robot's first status or a change of "finished": journal now
  std::chrono::steady_clock::time_point last_snapshot_{};  ///< when refresh_snapshot last ran
  double unshown_keyframe_wall_s_ = -1;  ///< wall clock (epoch s) of the oldest keyframe no snapshot showed yet
  int restored_records_ = 0;
  int journal_commits_ = 0;
  double journal_commit_s_ = 0;  ///< wall time spent committing (fsync included)
  std::vector<std::string> restore_skipped_;

  std::map<RobotId, RobotLink> links_;
  LatestSnapshot latest_snapshot_;  ///< handed to the console's HTTP threads
  std::atomic<bool> stop_{false};
  uint64_t optimized_version_ = 0;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  int rejected_samples_ = 0;
  int refused_overwrites_ = 0;           ///< samples that would have overwritten a stored one (AddStatus::kConflict)
  int spoofed_samples_ = 0;              ///< samples whose writer does not hold their robot's certificate
  RobotSessions sessions_;               ///< (robot, session) on the wire -> the base's robot id
  size_t landmark_events_reported_ = 0;  ///< mapper_.landmark_link_events() already logged
  std::map<RobotId, std::string> alignments_reported_;  ///< the operator alignments' verdicts already logged
};

}  // namespace cairn::base
