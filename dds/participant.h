#pragma once
// One Fast DDS domain participant per process, configured for Cairn's links: unicast discovery
// through initial peers (ad hoc Wi-Fi gives no multicast to count on), a large shared-memory
// segment for same-host big samples, an optional flow controller for large data on slow links, and
// optional DDS Security (authentication and encryption) for a radio link anyone can listen to.
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace cairn::dds {

struct ParticipantOptions {
  int domain_id = 0;
  std::string name = "cairn";
  /// Unicast discovery peers (IPv4). Loopback is always added so same-host processes meet.
  std::vector<std::string> initial_peers;
  /// How many participant ids per peer discovery probes (processes per host).
  uint32_t max_initial_peers_range = 32;
  bool use_shared_memory = true;
  uint32_t shm_segment_bytes = 32u << 20;  ///< default 512 KiB is too small for RGB-D frames
  /// Flow controller for large samples (objects); 0 = unlimited. Set below the link rate.
  uint32_t large_data_bytes_per_sec = 0;
  /// DDS Security: a folder with ca.pem, cert.pem and key.pem (deploy/security/make_certs.sh).
  /// Set, the participant talks only to participants whose certificates the same CA signed
  /// (PKI-DH), and every RTPS message it sends is encrypted (AES-GCM). Empty: no security.
  std::string security_dir;
};

constexpr const char* kLargeDataFlowController = "cairn_large_data";

/// Owns the participant, one publisher and one subscriber; registers types and topics once.
class Participant {
 public:
  /// Returns nullptr and sets `error` when the participant cannot be created.
  static std::unique_ptr<Participant> create(const ParticipantOptions& options, std::string* error);
  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  /// The topic named `name` of type `PubSubType` (registered on first use).
  template <typename PubSubType>
  eprosima::fastdds::dds::Topic* topic(const std::string& name) {
    auto it = topics_.find(name);
    if (it != topics_.end()) return it->second;
    eprosima::fastdds::dds::TypeSupport type(new PubSubType());
    return register_topic(name, type);
  }

  eprosima::fastdds::dds::DomainParticipant* get() { return participant_; }
  eprosima::fastdds::dds::Publisher* publisher() { return publisher_; }
  eprosima::fastdds::dds::Subscriber* subscriber() { return subscriber_; }
  const ParticipantOptions& options() const { return options_; }

 private:
  explicit Participant(const ParticipantOptions& options) : options_(options) {}
  eprosima::fastdds::dds::Topic* register_topic(const std::string& name, eprosima::fastdds::dds::TypeSupport type);

  ParticipantOptions options_;
  eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
  eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
  std::map<std::string, eprosima::fastdds::dds::Topic*> topics_;
};

}  // namespace cairn::dds
