#include "dds/ros2_endpoints.h"

namespace cairn::dds {

using namespace eprosima::fastdds::dds;

DataReaderQos ros2_reader_qos(Ros2Qos profile, int depth) {
  DataReaderQos q = DATAREADER_QOS_DEFAULT;
  q.endpoint().history_memory_policy = eprosima::fastrtps::rtps::PREALLOCATED_WITH_REALLOC_MEMORY_MODE;
  q.history().kind = KEEP_LAST_HISTORY_QOS;
  q.history().depth = depth;
  // A best-effort reader matches reliable and best-effort writers alike: drivers use either.
  q.reliability().kind = profile == Ros2Qos::kSensorData ? BEST_EFFORT_RELIABILITY_QOS : RELIABLE_RELIABILITY_QOS;
  q.durability().kind = profile == Ros2Qos::kLatched ? TRANSIENT_LOCAL_DURABILITY_QOS : VOLATILE_DURABILITY_QOS;
  // Lossless: what has not been taken yet is never overwritten (the publisher resends instead).
  if (profile == Ros2Qos::kReliableSensorData) q.history().kind = KEEP_ALL_HISTORY_QOS;
  return q;
}

DataWriterQos ros2_writer_qos(Ros2Qos profile, int depth) {
  DataWriterQos q = DATAWRITER_QOS_DEFAULT;
  q.endpoint().history_memory_policy = eprosima::fastrtps::rtps::PREALLOCATED_WITH_REALLOC_MEMORY_MODE;
  q.history().kind = KEEP_LAST_HISTORY_QOS;
  q.history().depth = depth > 0 ? depth : profile == Ros2Qos::kLatched ? 1 : profile == Ros2Qos::kDefault ? 10 : 5;
  // Reliable writers serve both kinds of readers (RViz2 subscribes to most displays reliably).
  q.reliability().kind = RELIABLE_RELIABILITY_QOS;
  q.reliability().max_blocking_time = {0, 100'000'000};
  q.reliable_writer_qos().times.heartbeatPeriod = {0, 200'000'000};
  q.durability().kind = profile == Ros2Qos::kLatched ? TRANSIENT_LOCAL_DURABILITY_QOS : VOLATILE_DURABILITY_QOS;
  return q;
}

std::string ros2_dds_topic(const std::string& ros_namespace, const std::string& name) {
  auto trim = [](std::string s) {
    while (!s.empty() && s.front() == '/') s.erase(s.begin());
    while (!s.empty() && s.back() == '/') s.pop_back();
    return s;
  };
  const std::string ns = trim(ros_namespace), n = trim(name);
  return "rt/" + (ns.empty() ? n : ns + "/" + n);
}

}  // namespace cairn::dds
