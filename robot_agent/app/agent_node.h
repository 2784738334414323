#pragma once
// The robot agent's DDS side around its core: sensor readers in, AgentPipeline, keyframe/object/
// status writers out; acks and corrections from the base station in. Single-threaded: run() polls.
// Data flow: sensor topics -> dds::from_msg -> AgentPipeline -> dds::to_msg -> keyframe/object.
#include <atomic>
#include <chrono>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "cairn_msgsPubSubTypes.h"
#include "common/logging.h"
#include "dds/endpoints.h"
#include "robot_agent/app/log_source.h"
#include "robot_agent/app/outbox.h"
#include "robot_agent/app/ros2_input.h"
#include "robot_agent/app/send_window.h"
#include "robot_agent/core/agent_pipeline.h"
#include "robot_agent/core/navigation/breadcrumbs.h"
#include "robot_agent/core/navigation/mission_behaviour.h"
#include "robot_agent/core/navigation/navigator.h"
#include "robot_agent/core/navigation/operator_orders.h"
#include "robot_agent/core/navigation/own_exploration.h"

namespace cairn::agent {

/// What one publish() sends, converted to DDS samples once (with this run's session): the outbox
/// keeps these samples' bytes and the writers write them (a keyframe's scan is compressed once).
struct OutgoingSamples {
  std::vector<cairn_msgs::Keyframe> keyframes;
  std::vector<cairn_msgs::ObjectReport> objects;
  std::optional<cairn_msgs::KeyframePoses> keyframe_poses;
  bool empty() const { return keyframes.empty() && objects.empty() && !keyframe_poses; }
};

struct AgentNodeOptions {
  int domain_id = 0;
  std::vector<std::string> peers;  ///< unicast discovery peers (IPv4), e.g. the base station
  std::string security_dir;        ///< DDS Security identity (dds::ParticipantOptions); empty = off
  /// This run's session id, in every sample it sends; the base's acks, goals and commands for other
  /// sessions are ignored. 0: a random one is drawn at start. A restarted agent (its map and local
  /// frame gone) is a new session the base keeps apart (base_station/core/robot_sessions.h).
  uint32_t session = 0;
  double status_period_s = 0.5;
  /// The outbox on disk (SQLite, robot_agent/app/outbox.h): what this run produces is kept there
  /// until the base acknowledges it, and what an earlier run left (a crash, a power cut) is resent
  /// first under its own session. Empty: no outbox (what is unacknowledged dies with the process).
  std::string outbox_path;
  /// How long to wait at the end for the base to store everything; 0 = as long as the process runs
  /// (the radio may be cut for minutes: what the robot found is kept and sent when it is back).
  double ack_timeout_s = 0.0;
  /// This robot's share of the radio in bytes/s (objects, keyframes, keyframe poses in that
  /// order of priority; dds::ParticipantOptions::link_budget_bytes_per_sec); 0 = unlimited.
  uint32_t link_budget_bytes_per_sec = 0;
  /// With a link budget: keyframes written to DDS and not yet acknowledged by the base at most;
  /// the rest wait in the agent (robot_agent/app/send_window.h says why).
  int keyframes_in_flight = 6;
  bool navigate = true;  ///< drive the robot (cmd_vel); off when replaying a log
  /// Sensors from a ROS 2 robot's drivers (cairn_agent --ros2) instead of Cairn's sensor topics.
  std::optional<Ros2InputOptions> ros2;
  NavigatorOptions navigator;
  MissionBehaviourOptions behaviour;
  OwnExplorationOptions own_exploration;
};

/// Where the sensor readings come from: the robot's DDS sensor topics (simulator or driver), or a
/// recorded CARMEN log replayed in-process.
struct SensorInput {
  const CarmenLog* log = nullptr;           ///< nullptr = DDS sensor topics
  const RobotLogData* robot_log = nullptr;  ///< or this robot's part of a multi-robot log
  LogSourceOptions log_options;
};

class AgentNode {
 public:
  static std::unique_ptr<AgentNode> create(RobotId robot, const AgentOptions& core_options,
                                           const AgentNodeOptions& options, const SensorInput& input,
                                           std::string* error);
  /// Runs until the mission clock says the input ended and the base acknowledged everything, or
  /// `stop` is set. Returns the process exit code: 3 when something was never acknowledged.
  int run(const std::atomic<bool>* stop = nullptr);

 private:
  AgentNode(RobotId robot, const AgentOptions& core_options, const AgentNodeOptions& options);
  bool poll_inputs();  ///< true when anything arrived
  void publish(const AgentOutputs& outputs);
  void publish_status(bool finished);
  bool base_has_everything();
  /// "acknowledged: keyframes 12 of 40, objects 1 of 2" (what the base has of what was sent).
  std::string delivery_report() const;
  /// Writes the newest update of each object and the newest keyframe poses once what was written
  /// before has been acknowledged (why: agent_node.cpp). True when nothing waits.
  bool send_waiting_updates();
  void write_keyframes();  ///< those keyframe_window_ releases
  /// Keyframe, object and keyframe-pose payloads written so far.
  uint64_t bytes_sent() const;
  /// Writes this run's outputs (publish() holds them back while an earlier session goes first).
  void write_outputs(const OutgoingSamples& samples);

  // The outbox (agent_node_outbox.cpp).
  struct EarlierSession {
    OutboxSession held;               ///< what an earlier run left unacknowledged
    size_t written = 0;               ///< held.items written so far
    double written_at_s = -1;         ///< when the last of them was written (run time)
    bool heard = false;               ///< the base acknowledged this session at least once
    int32_t acked_keyframe_seq = -1;  ///< the newest ack for it
    int32_t acked_objects = 0;
  };
  bool open_outbox(std::string* error);
  void keep(const OutgoingSamples& samples);  ///< into the outbox before anything is written
  /// True once the base has heard every earlier session: before, this run sends nothing.
  bool own_session_may_speak();
  void resend_earlier();
  void take_earlier_ack(const cairn_msgs::Ack& a);
  void note_own_ack();        ///< acknowledged keyframes leave the outbox
  void forget_own_session();  ///< the base has everything: the outbox forgets this run
  std::string earlier_report() const;
  std::unique_ptr<Outbox> outbox_;
  std::deque<EarlierSession> earlier_;
  std::vector<OutgoingSamples> held_outputs_;  ///< this run's, while an earlier session goes first
  int32_t outbox_acked_seq_ = -1;
  bool heard_any_ack_ = false;

  /// True for a sample from the base meant for this robot's running session.
  template <typename Msg>
  bool for_me(const Msg& m) const {
    return m.robot_id() == robot_.value && m.session() == session_;
  }

  template <typename Msg>
  Msg with_session(Msg m) const {
    m.session(session_);
    return m;
  }

  RobotId robot_;
  uint32_t session_ = 0;
  AgentNodeOptions options_;
  AgentPipeline pipeline_;
  std::shared_ptr<spdlog::logger> log_;
  std::unique_ptr<dds::Participant> participant_;
  std::unique_ptr<dds::Reader<dds::OdometryTopic>> odometry_in_;
  std::unique_ptr<dds::Reader<dds::LaserScanTopic>> laser_in_;
  std::unique_ptr<dds::Reader<dds::RgbdTopic>> rgbd_in_;
  std::unique_ptr<dds::Reader<dds::ClockTopic>> clock_in_;
  std::unique_ptr<dds::Reader<dds::AckTopic>> ack_in_;
  std::unique_ptr<dds::Reader<dds::GoalTopic>> goal_in_;
  std::unique_ptr<dds::Reader<dds::OperatorCommandTopic>> command_in_;
  std::unique_ptr<dds::Reader<dds::KeepOutTopic>> keep_out_in_;
  std::unique_ptr<dds::Writer<dds::KeyframeTopic>> keyframe_out_;
  std::unique_ptr<dds::Writer<dds::ObjectTopic>> object_out_;
  std::unique_ptr<dds::Writer<dds::KeyframePosesTopic>> keyframe_poses_out_;
  std::unique_ptr<dds::Writer<dds::StatusTopic>> status_out_;

  std::unique_ptr<LogSource> log_source_;     ///< set when replaying a log instead of DDS input
  std::unique_ptr<Ros2SensorInput> ros2_in_;  ///< set with --ros2: the robot's ROS 2 drivers
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  bool input_finished_ = false;
  // Before the first scan, the laser counts as silent by arrival time too (set_stamps_may_judge_laser).
  std::optional<std::chrono::steady_clock::time_point> first_odometry_arrival_;
  bool any_scan_arrived_ = false;
  int32_t last_keyframe_seq_ = -1;  ///< the newest keyframe made (written, or waiting to be)
  int32_t acked_keyframe_seq_ = -1;
  /// Made, waiting for room in flight (AgentNodeOptions::keyframes_in_flight; no limit without a budget).
  SendWindow<cairn_msgs::Keyframe> keyframe_window_;
  int acked_object_count_ = 0;
  std::set<int32_t> objects_published_;
  std::optional<cairn_msgs::KeyframePoses> waiting_poses_;       ///< newest estimate not written yet
  std::map<int32_t, cairn_msgs::ObjectReport> waiting_objects_;  ///< newest update per object not written yet
  int bad_samples_ = 0;
  int ros2_refused_ = 0;  ///< ROS 2 messages refused so far (logged as the count grows)
  struct Probe {
    uint64_t base_ns = 0;     ///< the newest ack's probe (the base's clock)
    int64_t received_ns = 0;  ///< when it arrived here (dds::reception_clock_ns)
  } probe_;  ///< echoed in each status: the base measures the link's round trip (base/core/round_trip.h)
  // Navigation (agent_node_navigation.cpp): goals in, cmd_vel out.
  void take_goal(const cairn_msgs::ExplorationGoal& g);
  void take_command(const cairn_msgs::OperatorCommand& c);
  /// The operator's keep-out areas in this robot's frame: its planner and own exploration obey them.
  void take_keep_out(const cairn_msgs::KeepOutAreas& m);
  /// The operator's newest command, applied before the scan's navigation step.
  void apply_operator_action();
  void heard_from_base();
  void drive(const AgentOutputs& outputs);
  NavStatus nav_status() const;
  Navigator navigator_;
  MissionBehaviour behaviour_;
  uint32_t keep_out_version_ = 0;    ///< the keep-out areas held (0: none told)
  OperatorOrders operator_;          ///< the operator's commands outrank behaviour_ until resumed
  CommandReport published_command_;  ///< the command report in the newest status sent
  OwnExplorationOptions own_options_;
  Breadcrumbs breadcrumbs_;  ///< the way back home if its own map shows none
  std::unique_ptr<dds::Writer<dds::CmdVelTopic>> cmd_out_;
  SE2 pose_;                  ///< newest processed scan's pose, local frame
  StampNs last_scan_ns_ = 0;  ///< its stamp: the agent's mission time
  double distance_m_ = 0;
  DriveTarget reported_goal_;  ///< the newest goal driven, and its state (also once ended)
  NavState reported_state_ = NavState::kIdle;
  RobotActivity last_activity_ = RobotActivity::kWaiting;
  int last_rate_scans_ = 0;        ///< for the scan rate in the status message
  int last_stalled_scans_ = 0;     ///< AgentStats::scans_odometry_stalled at the last warning
  int last_laser_recoveries_ = 0;  ///< AgentStats::laser_recoveries at the last log line
  double last_rate_time_s_ = 0.0;
};

}  // namespace cairn::agent
