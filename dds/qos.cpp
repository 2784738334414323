#include "dds/qos.h"

#include "dds/participant.h"

namespace cairn::dds {

using namespace eprosima::fastdds::dds;

namespace {

void reliable_common(DataWriterQos& q, const QosOptions& options) {
  q.reliability().kind = RELIABLE_RELIABILITY_QOS;
  q.reliability().max_blocking_time = {5, 0};
  // The default 3 s heartbeat makes recovery of lost fragments slow on a lossy link.
  q.reliable_writer_qos().times.heartbeatPeriod = to_duration(options.heartbeat_period_s);
  q.reliable_writer_qos().times.nackResponseDelay = {0, 5'000'000};
}

// Instance limits: Fast DDS defaults to 10 instances per endpoint, far too few for a team.
constexpr int32_t kMaxRobots = 64;
constexpr int32_t kMaxObjectsPerRobot = 1000;

template <typename Q>
void set_limits(Q& q, int32_t instances, int32_t samples_per_instance) {
  // Fast DDS requires max_samples >= max_instances * max_samples_per_instance.
  q.resource_limits().max_instances = instances;
  q.resource_limits().max_samples_per_instance = samples_per_instance;
  q.resource_limits().max_samples = instances * samples_per_instance;
}

}  // namespace

DataWriterQos writer_qos(TopicKind kind, const QosOptions& options) {
  DataWriterQos q = DATAWRITER_QOS_DEFAULT;
  q.endpoint().history_memory_policy = eprosima::fastrtps::rtps::PREALLOCATED_WITH_REALLOC_MEMORY_MODE;
  switch (kind) {
    case TopicKind::kSensor:
      reliable_common(q, options);
      q.history().kind = KEEP_ALL_HISTORY_QOS;
      // Volatile keep-all: acknowledged samples are dropped only when the history is full, so the
      // limit is the memory a driver holds (RGB-D frames are 384 KB: 2000 of them were 768 MB per
      // robot); 200 is 20 s of laser and 100 s of RGB-D an agent may lag behind, and a write into a
      // history full of unacknowledged samples blocks (max_blocking_time), it never drops one.
      set_limits(q, 4, 200);
      q.publish_mode().kind = ASYNCHRONOUS_PUBLISH_MODE;
      break;
    case TopicKind::kClock:
      reliable_common(q, options);
      q.durability().kind = TRANSIENT_LOCAL_DURABILITY_QOS;
      q.history().kind = KEEP_LAST_HISTORY_QOS;
      q.history().depth = 1;
      break;
    case TopicKind::kKeyframe:
      reliable_common(q, options);
      q.durability().kind = TRANSIENT_LOCAL_DURABILITY_QOS;
      q.history().kind = KEEP_ALL_HISTORY_QOS;
      set_limits(q, 4, 100000);
      q.publish_mode().kind = ASYNCHRONOUS_PUBLISH_MODE;
      break;
    case TopicKind::kObject:
      reliable_common(q, options);
      q.durability().kind = TRANSIENT_LOCAL_DURABILITY_QOS;
      // Keep all: every version of an object is delivered; acknowledged ones make room. With keep
      // last 1 a version replaced while its fragments were still crossing a 250 kbit/s radio was
      // announced as a GAP, and the base aborted on Fast DDS 2.9's assertion in
      // DataReaderHistory::update_instance_nts (core dump: the change was this topic's).
      q.history().kind = KEEP_ALL_HISTORY_QOS;
      // One instance per object: the default max_instances (10) would refuse the 11th object.
      set_limits(q, kMaxObjectsPerRobot, 100);
      q.publish_mode().kind = ASYNCHRONOUS_PUBLISH_MODE;
      break;
    case TopicKind::kStatus:
      q.reliability().kind = BEST_EFFORT_RELIABILITY_QOS;
      q.history().kind = KEEP_LAST_HISTORY_QOS;
      q.history().depth = 1;
      break;
    case TopicKind::kAck:
    case TopicKind::kCommand:
    case TopicKind::kCorrection:
    case TopicKind::kKeyframePoses:
    case TopicKind::kGoal:
      reliable_common(q, options);
      if (kind != TopicKind::kAck && kind != TopicKind::kCommand) q.durability().kind = TRANSIENT_LOCAL_DURABILITY_QOS;
      q.history().kind = KEEP_LAST_HISTORY_QOS;
      q.history().depth = 1;
      set_limits(q, kMaxRobots, 1);  // one instance per robot
      break;
  }
  if (options.link_budgeted) {
    // On a rate-limited link every sample, retransmissions too, is paced below the link rate, the
    // most urgent first; a burst (the flush at the end of a mission) no longer overflows the
    // link's queue and keeps it saturated with retransmissions.
    q.publish_mode().kind = ASYNCHRONOUS_PUBLISH_MODE;
    q.publish_mode().flow_controller_name = kLinkFlowController;
    q.properties().properties().emplace_back("fastdds.sfc.priority", std::to_string(link_priority(kind)));
  }
  return q;
}

int link_priority(TopicKind kind) {
  switch (kind) {
    case TopicKind::kObject:
      return -10;  // a victim or hazard reaches the team first
    case TopicKind::kKeyframe:
      return 0;
    case TopicKind::kKeyframePoses:
      return 5;  // the newest estimate, when the rest has gone
    default:
      return 10;
  }
}

DataReaderQos reader_qos(TopicKind kind) {
  DataReaderQos q = DATAREADER_QOS_DEFAULT;
  q.endpoint().history_memory_policy = eprosima::fastrtps::rtps::PREALLOCATED_WITH_REALLOC_MEMORY_MODE;
  const bool reliable = kind != TopicKind::kStatus;
  q.reliability().kind = reliable ? RELIABLE_RELIABILITY_QOS : BEST_EFFORT_RELIABILITY_QOS;
  // A reader that knows a writer but has had no heartbeat from it asks for its data "preemptively"
  // after this delay, then after twice it, and so on (Fast DDS: 70 ms). On a 50 kbit/s radio, while
  // the endpoint announcements were still being repeated, each agent's four readers of the base's
  // topics sent 12 such requests a second each, all 25 s long (2 166 packets), which crowded out the
  // announcements the base needed before it could answer: nothing was delivered in 400 s. From 1 s
  // the two-robot mission delivers everything at 50 kbit/s (docs/benchmarks.md "The slow radio").
  // A writer pushes its data to a reader it matches anyway; the request only covers a lost first
  // heartbeat.
  q.reliable_reader_qos().times.initialAcknackDelay = {1, 0};
  switch (kind) {
    case TopicKind::kSensor:
    case TopicKind::kKeyframe:
      q.history().kind = KEEP_ALL_HISTORY_QOS;
      set_limits(q, kMaxRobots, 100000);  // a deep reader history: nothing is dropped
      if (kind == TopicKind::kKeyframe) q.durability().kind = TRANSIENT_LOCAL_DURABILITY_QOS;
      break;
    case TopicKind::kObject:
      // Keyed by (robot, object): every robot's every object is an instance; updates of one
      // object queue until taken.
      q.durability().kind = TRANSIENT_LOCAL_DURABILITY_QOS;
      q.history().kind = KEEP_ALL_HISTORY_QOS;
      set_limits(q, kMaxRobots * kMaxObjectsPerRobot, 8);
      break;
    case TopicKind::kClock:
    case TopicKind::kCorrection:
    case TopicKind::kKeyframePoses:
    case TopicKind::kGoal:
      q.durability().kind = TRANSIENT_LOCAL_DURABILITY_QOS;
      q.history().kind = KEEP_LAST_HISTORY_QOS;
      q.history().depth = 1;
      set_limits(q, kMaxRobots, 1);
      break;
    case TopicKind::kStatus:
    case TopicKind::kAck:
    case TopicKind::kCommand:
      q.history().kind = KEEP_LAST_HISTORY_QOS;
      q.history().depth = 1;
      set_limits(q, kMaxRobots, 1);
      break;
  }
  return q;
}

}  // namespace cairn::dds
