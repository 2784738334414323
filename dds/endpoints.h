#pragma once
// Typed writer and reader over a Participant. Readers are polled with take_all() from the app's
// own loop (no listener threads touching app state), which keeps the app single-threaded.
#include <fastdds/dds/core/status/PublicationMatchedStatus.hpp>
#include <fastdds/dds/core/status/SubscriptionMatchedStatus.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "dds/participant.h"
#include "dds/qos.h"

namespace cairn::dds {

using eprosima::fastrtps::types::ReturnCode_t;

template <typename Msg, typename PubSubType>
class Writer {
 public:
  Writer(Participant& participant, const std::string& topic_name, TopicKind kind, const QosOptions& options = {}) {
    auto* topic = participant.topic<PubSubType>(topic_name);
    publisher_ = participant.publisher();
    if (topic) writer_ = publisher_->create_datawriter(topic, writer_qos(kind, options));
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
  static eprosima::fastrtps::Duration_t to_duration(double s) {
    return eprosima::fastrtps::Duration_t(int32_t(s), uint32_t((s - int32_t(s)) * 1e9));
  }
  PubSubType type_;
  eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
  eprosima::fastdds::dds::DataWriter* writer_ = nullptr;
  uint64_t samples_ = 0;
  uint64_t bytes_ = 0;
};

template <typename Msg, typename PubSubType>
class Reader {
 public:
  Reader(Participant& participant, const std::string& topic_name, TopicKind kind) {
    auto* topic = participant.topic<PubSubType>(topic_name);
    subscriber_ = participant.subscriber();
    if (topic) reader_ = subscriber_->create_datareader(topic, reader_qos(kind));
  }
  ~Reader() {
    if (reader_) subscriber_->delete_datareader(reader_);
  }
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  bool ok() const { return reader_ != nullptr; }
  /// Takes every valid sample available now, in arrival order.
  std::vector<Msg> take_all() {
    std::vector<Msg> out;
    if (!reader_) return out;
    Msg msg;
    eprosima::fastdds::dds::SampleInfo info;
    while (reader_->take_next_sample(&msg, &info) == ReturnCode_t::RETCODE_OK) {
      if (info.valid_data) out.push_back(msg);
    }
    return out;
  }
  int matched_writers() const {
    eprosima::fastdds::dds::SubscriptionMatchedStatus st;
    if (!reader_ || reader_->get_subscription_matched_status(st) != ReturnCode_t::RETCODE_OK) return 0;
    return st.current_count;
  }

 private:
  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
  eprosima::fastdds::dds::DataReader* reader_ = nullptr;
};

}  // namespace cairn::dds
