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
  /// How many participant ids discovery probes on this host (processes per host).
  uint32_t max_initial_peers_range = 32;
  /// How many participant ids it probes on each remote peer. Every probe is a participant
  /// announcement (~600 B) sent every announcement period for the whole mission: 32 per peer were
  /// 19 kB every 3 s per process, more than a 250 kbit/s radio's queue holds (it dropped them and
  /// the data behind them). Processes a peer holds beyond these are still found: they probe us.
  uint32_t remote_peer_participants = 4;
  /// Participant announcement period and lease (Fast DDS defaults 3 s / 20 s). A slow link wants
  /// fewer announcements; the lease stays several periods so that lost ones do not unmatch a peer.
  double announcement_period_s = 3.0;
  double lease_duration_s = 20.0;
  /// Only participants on this host (Fast DDS host id) are discovered: the simulator's sensor
  /// topics are the robots' onboard buses, and the base station across the radio must not
  /// exchange endpoint discovery with it (on a 50 kbit/s link that exchange alone filled the link).
  /// Ignored with security_dir (the GUID prefix then comes from the certificate, not the host).
  bool same_host_only = false;
  bool use_shared_memory = true;
  uint32_t shm_segment_bytes = 32u << 20;  ///< default 512 KiB is too small for RGB-D frames
  /// This process's share of the radio link in bytes/s; 0 = unlimited. Set, the writers that ask
  /// for it (QosOptions::link_priority) send through one flow controller at this rate that serves
  /// the highest priority first (Fast DDS HIGH_PRIORITY scheduler).
  uint32_t link_budget_bytes_per_sec = 0;
  /// DDS Security: a folder with ca.pem, cert.pem and key.pem (deploy/security/make_certs.sh).
  /// Set, the participant talks only to participants whose certificates the same CA signed
  /// (PKI-DH), and every RTPS message it sends is encrypted (AES-GCM). Empty: no security.
  std::string security_dir;
};

/// Discovery on a slow radio (a process with a link budget, a base told --slow-link): a
/// participant announcement every 10 s instead of 3, a lease of six announcements.
constexpr double kSlowLinkAnnouncementPeriod_s = 10.0;
constexpr double kSlowLinkLeaseDuration_s = 60.0;

constexpr const char* kLinkFlowController = "cairn_link_budget";
/// Bytes the link flow controller sends per period, which is also the largest piece Fast DDS cuts
/// a sample into: a keyframe (~1.2 kB) and a status go whole, an object (~10 kB) in four pieces of
/// two radio frames each. With one frame's worth (1300 B) a period carried one sample at most (a
/// keyframe and a status never fitted together): four robots on 250 kbit/s fell 45-65 keyframes
/// behind at real time.
constexpr uint32_t kLinkPeriodBytes = 2600;

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
