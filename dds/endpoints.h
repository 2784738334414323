#pragma once
// Typed writer and reader of one topic of dds/topics.h over a Participant:
//   dds::Writer<dds::KeyframeTopic> keyframes(participant, qos_options);
//   dds::Reader<dds::LaserScanTopic> scans(participant, robot);  // per-robot topics take the robot
// Readers are polled with take_all() from the app's own loop (no listener threads touching app
// state), which keeps the app single-threaded.
#include <fastdds/dds/core/status/PublicationMatchedStatus.hpp>
#include <fastdds/dds/core/status/SubscriptionMatchedStatus.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "common/ids.h"
#include "dds/identity.h"
#include "dds/participant.h"
#include "dds/qos.h"
#include "dds/topics.h"

namespace cairn::dds {

/// The clock Fast DDS stamps each sample's arrival with (SampleInfo::reception_timestamp: the
/// system clock, ns since the Unix epoch). The link's round trip is measured on it.
inline int64_t reception_clock_ns() {
  eprosima::fastrtps::rtps::Time_t now;
  eprosima::fastrtps::rtps::Time_t::now(now);
  return now.to_ns();
}

using eprosima::fastrtps::types::ReturnCode_t;

template <typename Topic>
class Writer {
  static_assert(kListedTopic<Topic>, "add the topic to AllTopics in dds/topics.h");

 public:
  using Msg = typename Topic::Msg;

  /// A writer of a shared topic.
  explicit Writer(Participant& participant, const QosOptions& options = {}) {
    create(participant, topic_name<Topic>(), options);
  }
  /// A writer of the per-robot topic of `robot`.
  Writer(Participant& participant, RobotId robot, const QosOptions& options = {}) {
    create(participant, topic_name<Topic>(robot), options);
  }
  ~Writer() {
    if (writer_) publisher_->delete_datawriter(writer_);
  }
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  bool ok() const { return writer_ != nullptr; }
  /// False when the sample could not be queued (history full past max_blocking_time).
  bool write(const Msg& msg) {
    if (!writer_) return false;
    Msg copy = msg;  // write() takes a non-const pointer
    if (!writer_->write(&copy)) return false;
    ++samples_;
    bytes_ += type_.getSerializedSizeProvider(&copy)();
    return true;
  }
  /// Waits until every matched reliable reader acknowledged all samples.
  bool wait_for_acknowledgments(double timeout_s) {
    if (!writer_) return false;
    return writer_->wait_for_acknowledgments(to_duration(timeout_s)) == ReturnCode_t::RETCODE_OK;
  }
  int matched_readers() const {
    eprosima::fastdds::dds::PublicationMatchedStatus st;
    if (!writer_ || writer_->get_publication_matched_status(st) != ReturnCode_t::RETCODE_OK) return 0;
    return st.current_count;
  }
  uint64_t bytes_written() const { return bytes_; }
  uint64_t samples_written() const { return samples_; }

 private:
  void create(Participant& participant, const std::string& name, const QosOptions& options) {
    auto* topic = participant.topic<typename Topic::PubSub>(name);
    publisher_ = participant.publisher();
    if (topic) writer_ = publisher_->create_datawriter(topic, writer_qos(Topic::kKind, options));
  }
  typename Topic::PubSub type_;
  eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
  eprosima::fastdds::dds::DataWriter* writer_ = nullptr;
  uint64_t samples_ = 0;
  uint64_t bytes_ = 0;
};

template <typename Topic>
class Reader {
  static_assert(kListedTopic<Topic>, "add the topic to AllTopics in dds/topics.h");

 public:
  using Msg = typename Topic::Msg;

  /// A reader of a shared topic.
  explicit Reader(Participant& participant) { create(participant, topic_name<Topic>()); }
  /// A reader of the per-robot topic of `robot`.
  Reader(Participant& participant, RobotId robot) { create(participant, topic_name<Topic>(robot)); }
  ~Reader() {
    if (reader_) subscriber_->delete_datareader(reader_);
  }
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  bool ok() const { return reader_ != nullptr; }
  /// A sample with the GUID prefix of the participant that wrote it (dds/identity.h), and when it
  /// arrived (reception_clock_ns(): before the app's poll took it).
  struct FromWriter {
    Msg msg;
    GuidPrefix writer{};
    int64_t received_ns = 0;
  };
  /// Takes every valid sample available now, in arrival order, each with its writer's participant.
  std::vector<FromWriter> take_all_from_writers() {
    std::vector<FromWriter> out;
    if (!reader_) return out;
    FromWriter s;
    eprosima::fastdds::dds::SampleInfo info;
    while (reader_->take_next_sample(&s.msg, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;
      for (size_t i = 0; i < s.writer.size(); ++i) s.writer[i] = info.publication_handle.value[i];
      s.received_ns = info.reception_timestamp.to_ns();
      out.push_back(s);
    }
    return out;
  }
  /// take_all_from_writers() without the writers.
  std::vector<Msg> take_all() {
    std::vector<Msg> out;
    for (FromWriter& s : take_all_from_writers()) out.push_back(std::move(s.msg));
    return out;
  }
  int matched_writers() const {
    eprosima::fastdds::dds::SubscriptionMatchedStatus st;
    if (!reader_ || reader_->get_subscription_matched_status(st) != ReturnCode_t::RETCODE_OK) return 0;
    return st.current_count;
  }

 private:
  void create(Participant& participant, const std::string& name) {
    auto* topic = participant.topic<typename Topic::PubSub>(name);
    subscriber_ = participant.subscriber();
    if (topic) reader_ = subscriber_->create_datareader(topic, reader_qos(Topic::kKind));
  }

  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
  eprosima::fastdds::dds::DataReader* reader_ = nullptr;
};

}  // namespace cairn::dds
