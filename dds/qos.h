#pragma once
// Per-topic QoS, in one place (the table in docs/architecture.md); each topic's kind is in dds/topics.h.
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>

namespace cairn::dds {

enum class TopicKind {
  kSensor,         ///< odometry, laser, RGB-D: reliable, keep all (a replay must not drop input)
  kClock,          ///< mission clock: reliable, transient local, keep last 1
  kKeyframe,       ///< reliable, transient local, keep all: the writer history is the outbox
  kObject,         ///< reliable, transient local, keep all (every version) per object
  kStatus,         ///< best effort, keep last 1
  kAck,            ///< reliable, keep last 1 per robot
  kCorrection,     ///< reliable, transient local, keep last 1 per robot
  kKeyframePoses,  ///< like kCorrection, agent -> base: only the newest estimate matters
  kGoal,           ///< like kCorrection: each robot's newest exploration goal
  kCommand,        ///< velocity command: reliable, volatile, keep last 1 (only the newest counts)
};

/// Seconds as a Fast DDS duration (timeouts, blocking times).
inline eprosima::fastrtps::Duration_t to_duration(double s) {
  return eprosima::fastrtps::Duration_t(int32_t(s), uint32_t((s - int32_t(s)) * 1e9));
}

struct QosOptions {
  /// Through the participant's link flow controller (ParticipantOptions::link_budget_bytes_per_sec),
  /// at the kind's priority: objects (a victim) first, then keyframes, then keyframe poses.
  bool link_budgeted = false;
  /// How often a reliable writer with unacknowledged samples asks its readers what they miss. The
  /// 200 ms default repairs losses fast on a LAN; on a slow radio four agents' heartbeats (and the
  /// base's acknowledgement traffic they provoke) took a third of 250 kbit/s: kSlowLinkHeartbeat_s.
  double heartbeat_period_s = 0.2;
};

constexpr double kSlowLinkHeartbeat_s = 1.0;

/// Priority of a kind on a budgeted link, Fast DDS's scale: -10 first .. 10 last.
int link_priority(TopicKind kind);

eprosima::fastdds::dds::DataWriterQos writer_qos(TopicKind kind, const QosOptions& options = {});
eprosima::fastdds::dds::DataReaderQos reader_qos(TopicKind kind);

}  // namespace cairn::dds
