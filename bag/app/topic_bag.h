#pragma once
// Cairn's DDS topics as MCAP channels: a TopicTap reads one topic and hands over each sample as
// the CDR bytes it travels in (with its reception time); a TopicPlayer takes those bytes back,
// checks that they decode to the topic's type, and writes the sample. Both are built from the
// topic table (dds/topics.h), so a new topic is recorded and replayed with no change here.
// Each channel's schema is the project's IDL (encoding "omgidl"), named by the type's IDL name.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/ids.h"
#include "dds/participant.h"

namespace cairn::bag {

/// The IDL every Cairn message type is defined in (idl/cairn_msgs.idl), the schema of its channels.
const std::string& cairn_idl_text();

struct TappedSample {
  int64_t received_ns = 0;
  std::vector<uint8_t> cdr;
};

class TopicTap {
 public:
  virtual ~TopicTap() = default;
  const std::string& topic() const { return topic_; }
  const std::string& type_name() const { return type_name_; }
  const std::string& schema_encoding() const { return schema_encoding_; }  ///< "omgidl" or "ros2msg"
  const std::string& schema_text() const { return schema_text_; }
  /// Every sample that arrived since the last call.
  virtual std::vector<TappedSample> take() = 0;

 protected:
  TopicTap(std::string topic, std::string type_name, std::string schema_encoding, std::string schema_text)
      : topic_(std::move(topic)),
        type_name_(std::move(type_name)),
        schema_encoding_(std::move(schema_encoding)),
        schema_text_(std::move(schema_text)) {}

 private:
  std::string topic_, type_name_, schema_encoding_, schema_text_;
};

/// A tap on every Cairn topic whose name `wanted` accepts; per-robot topics for robots 0..robot_count-1.
std::vector<std::unique_ptr<TopicTap>> make_taps(dds::Participant& participant, int robot_count,
                                                 const std::function<bool(const std::string&)>& wanted);

/// Taps on the ROS 2 topics the base publishes with --ros2 (base_station/app/ros2_output.h), under
/// their ROS names ("/map", "/tf", "/cairn/objects", "/cairn/object_clouds", "/robotN/path"), and
/// on each ROS 2 robot's own topics under namespace robotN ("/robotN/scan", "/robotN/odom",
/// "/robotN/cmd_vel": what cairn_agent --ros2 reads and writes). The robots' scan and odometry taps
/// are best effort (a driver's sensor publishers may be), or with `reliable` reliable and keep-all:
/// nothing lost, but only reliable publishers match (cairn_replay's).
std::vector<std::unique_ptr<TopicTap>> make_ros2_taps(dds::Participant& participant, int robot_count,
                                                      bool reliable = false);

enum class PlayResult { kWritten, kFilteredOut, kUndecodable, kWriteFailed };

class TopicPlayer {
 public:
  virtual ~TopicPlayer() = default;
  /// Decodes `cdr` as this topic's type and writes it, unless its robot is not in `robots` (empty: all).
  virtual PlayResult play(const std::vector<uint8_t>& cdr, const std::vector<int>& robots) = 0;
  virtual int matched_readers() const = 0;
  /// Waits until matched reliable readers acknowledged every sample written.
  virtual bool flush(double timeout_s) = 0;
};

/// The player of a recorded channel, or nullptr (with `why`) when `topic` is not one of Cairn's
/// topics or `type_name` is not its type.
std::unique_ptr<TopicPlayer> make_player(dds::Participant& participant, const std::string& topic,
                                         const std::string& type_name, std::string* why);

/// The --topics choice of cairn_record and cairn_replay: a topic whose name contains one of `words`
/// (every topic when there are none).
bool topic_wanted(const std::string& topic, const std::vector<std::string>& words);

/// The robot of a per-robot topic name ("cairn/robot3/odometry" -> 3), nullopt for a shared topic.
std::optional<int> robot_of_topic(const std::string& topic);

}  // namespace cairn::bag
