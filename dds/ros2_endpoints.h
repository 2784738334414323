#pragma once
// ROS 2 topics on the wire, without ROS 2: a ROS topic "/robot1/scan" is the DDS topic
// "rt/robot1/scan" of type sensor_msgs::msg::dds_::LaserScan_ (idl/ros2_msgs.idl), with ROS 2's
// QoS profiles (rmw_qos_profile_sensor_data and friends). Names are runtime strings (namespaces are
// the user's), unlike Cairn's own topic table (dds/topics.h).
//   dds::Ros2Reader<sensor_msgs::msg::dds_::LaserScan_PubSubType> scans(participant, "/scan", Ros2Qos::kSensorData);
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>

#include <string>
#include <vector>

#include "dds/participant.h"
#include "dds/qos.h"

namespace cairn::dds {

enum class Ros2Qos {
  kSensorData,  ///< best effort, volatile, keep last (matches every driver, reliable or not)
  /// Reliable, volatile, keep all: lossless from reliable publishers only (a bag replayed by
  /// cairn_replay, whose writers are reliable and keep a deep history).
  kReliableSensorData,
  kDefault,  ///< reliable, volatile, keep last 10 (cmd_vel, paths, markers)
  kLatched,  ///< reliable, transient local, keep last 1 (the map, as map_server offers it)
};

eprosima::fastdds::dds::DataReaderQos ros2_reader_qos(Ros2Qos profile, int depth);
/// `depth` 0: the profile's (5 sensor data, 10 default, 1 latched).
eprosima::fastdds::dds::DataWriterQos ros2_writer_qos(Ros2Qos profile, int depth = 0);

/// "rt" + the fully qualified ROS name: ("robot1", "scan") -> "rt/robot1/scan"; ("", "/map") -> "rt/map".
std::string ros2_dds_topic(const std::string& ros_namespace, const std::string& name);

template <typename PubSub>
class Ros2Reader {
 public:
  using Msg = typename PubSub::type;
  /// `depth`: samples kept until taken (a slow poll drops the oldest beyond it).
  Ros2Reader(Participant& participant, const std::string& dds_topic, Ros2Qos profile, int depth = 10) {
    if (auto* topic = participant.topic<PubSub>(dds_topic)) {
      subscriber_ = participant.subscriber();
      reader_ = subscriber_->create_datareader(topic, ros2_reader_qos(profile, depth));
    }
  }
  ~Ros2Reader() {
    if (reader_) subscriber_->delete_datareader(reader_);
  }
  Ros2Reader(const Ros2Reader&) = delete;
  Ros2Reader& operator=(const Ros2Reader&) = delete;
  bool ok() const { return reader_ != nullptr; }
  std::vector<Msg> take_all() {
    std::vector<Msg> out;
    Msg m;
    eprosima::fastdds::dds::SampleInfo info;
    while (reader_ && reader_->take_next_sample(&m, &info) == eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK) {
      if (info.valid_data) out.push_back(m);
    }
    return out;
  }

 private:
  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
  eprosima::fastdds::dds::DataReader* reader_ = nullptr;
};

template <typename PubSub>
class Ros2Writer {
 public:
  using Msg = typename PubSub::type;
  /// `depth` 0: the profile's history depth.
  Ros2Writer(Participant& participant, const std::string& dds_topic, Ros2Qos profile, int depth = 0) {
    if (auto* topic = participant.topic<PubSub>(dds_topic)) {
      publisher_ = participant.publisher();
      writer_ = publisher_->create_datawriter(topic, ros2_writer_qos(profile, depth));
    }
  }
  ~Ros2Writer() {
    if (writer_) publisher_->delete_datawriter(writer_);
  }
  Ros2Writer(const Ros2Writer&) = delete;
  Ros2Writer& operator=(const Ros2Writer&) = delete;
  bool ok() const { return writer_ != nullptr; }
  bool write(const Msg& msg) {
    Msg copy = msg;  // write() takes a non-const pointer
    return writer_ && writer_->write(&copy);
  }
  /// Waits until every matched reliable reader acknowledged all samples.
  bool wait_for_acknowledgments(double timeout_s) {
    return writer_ && writer_->wait_for_acknowledgments(to_duration(timeout_s)) ==
                          eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK;
  }
  int matched_readers() const {
    eprosima::fastdds::dds::PublicationMatchedStatus st;
    return writer_ && writer_->get_publication_matched_status(st) == eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK
               ? st.current_count
               : 0;
  }

 private:
  eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
  eprosima::fastdds::dds::DataWriter* writer_ = nullptr;
};

}  // namespace cairn::dds
