#include "dds/participant.h"

#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>
#include <limits.h>
#include <stdlib.h>
#include <unistd.h>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>

namespace cairn::dds {

using namespace eprosima::fastdds::dds;
using eprosima::fastdds::rtps::SharedMemTransportDescriptor;
using eprosima::fastdds::rtps::UDPv4TransportDescriptor;
using eprosima::fastrtps::rtps::IPLocator;
using eprosima::fastrtps::rtps::Locator_t;

namespace {

/// Fast DDS's builtin plugins: PKI-DH authentication, AES-GCM encryption of whole RTPS messages
/// (set by property, as no access-control plugin is configured: every authenticated team member
/// may use every topic). False with `error` naming the missing file.
bool add_security(const std::string& dir, DomainParticipantQos* qos, std::string* error) {
  auto file = [&](const char* name) { return dir + "/" + name; };
  for (const char* name : {"ca.pem", "cert.pem", "key.pem"}) {
    if (::access(file(name).c_str(), R_OK) != 0) {
      if (error) *error = "DDS security: cannot read " + file(name) + " (make it with deploy/security/make_certs.sh)";
      return false;
    }
  }
  auto& props = qos->properties().properties();
  props.emplace_back("dds.sec.auth.plugin", "builtin.PKI-DH");
  props.emplace_back("dds.sec.auth.builtin.PKI-DH.identity_ca", "file://" + file("ca.pem"));
  props.emplace_back("dds.sec.auth.builtin.PKI-DH.identity_certificate", "file://" + file("cert.pem"));
  props.emplace_back("dds.sec.auth.builtin.PKI-DH.private_key", "file://" + file("key.pem"));
  // The handshake is retried for as long as a mission lasts. Fast DDS's default (10 requests from
  // 125 ms, period x1.5) gives up after about 14 s and never tries that peer again: a robot whose
  // first handshake met a busy base or a bad radio patch stayed deaf to the team for the whole
  // mission (seen in CI). 1000 requests from 250 ms, period x1.01: a retry within 1 s for the first
  // minute, within 6 s after ten minutes, within 40 s after an hour.
  props.emplace_back("dds.sec.auth.builtin.PKI-DH.max_handshake_requests", "1000");
  props.emplace_back("dds.sec.auth.builtin.PKI-DH.initial_handshake_resend_period", "250");
  props.emplace_back("dds.sec.auth.builtin.PKI-DH.handshake_resend_period_gain", "1.01");
  props.emplace_back("dds.sec.crypto.plugin", "builtin.AES-GCM-GMAC");
  props.emplace_back("rtps.participant.rtps_protection_kind", "ENCRYPT");
  return true;
}

}  // namespace

std::unique_ptr<Participant> Participant::create(const ParticipantOptions& options, std::string* error) {
  std::unique_ptr<Participant> p(new Participant(options));
  DomainParticipantQos qos = PARTICIPANT_QOS_DEFAULT;
  qos.name(options.name);

  // Transports: UDPv4 always (the radio link), shared memory for same-host peers.
  qos.transport().use_builtin_transports = false;
  auto udp = std::make_shared<UDPv4TransportDescriptor>();
  udp->maxInitialPeersRange = options.max_initial_peers_range;
  qos.transport().user_transports.push_back(udp);
  if (options.use_shared_memory) {
    auto shm = std::make_shared<SharedMemTransportDescriptor>();
    shm->segment_size(options.shm_segment_bytes);
    shm->maxInitialPeersRange = options.max_initial_peers_range;
    qos.transport().user_transports.push_back(shm);
  }

  // Unicast discovery: loopback plus configured peers.
  std::vector<std::string> peers = options.initial_peers;
  peers.insert(peers.begin(), "127.0.0.1");
  for (const auto& address : peers) {
    Locator_t locator;
    if (!IPLocator::setIPv4(locator, address)) {
      if (error) *error = "invalid initial peer address '" + address + "'";
      return nullptr;
    }
    locator.kind = LOCATOR_KIND_UDPv4;
    qos.wire_protocol().builtin.initialPeersList.push_back(locator);
  }

  if (options.large_data_bytes_per_sec > 0) {
    auto flow = std::make_shared<eprosima::fastdds::rtps::FlowControllerDescriptor>();
    flow->name = kLargeDataFlowController;
    flow->period_ms = 50;
    flow->max_bytes_per_period = int32_t(options.large_data_bytes_per_sec / 20);
    qos.flow_controllers().push_back(flow);
  }

  if (!options.security_dir.empty()) {
    std::string dir = options.security_dir;
    char resolved[PATH_MAX];
    if (::realpath(dir.c_str(), resolved)) dir = resolved;  // file:// URIs want an absolute path
    if (!add_security(dir, &qos, error)) return nullptr;
  }

  p->participant_ = DomainParticipantFactory::get_instance()->create_participant(options.domain_id, qos);
  if (!p->participant_) {
    if (error) {
      *error = "cannot create DDS participant on domain " + std::to_string(options.domain_id) +
               (options.security_dir.empty() ? ""
                                             : " (DDS security from " + options.security_dir +
                                                   ": are cert.pem and key.pem a pair signed by ca.pem?)");
    }
    return nullptr;
  }
  p->publisher_ = p->participant_->create_publisher(PUBLISHER_QOS_DEFAULT);
  p->subscriber_ = p->participant_->create_subscriber(SUBSCRIBER_QOS_DEFAULT);
  if (!p->publisher_ || !p->subscriber_) {
    if (error) *error = "cannot create DDS publisher/subscriber";
    return nullptr;
  }
  return p;
}

Topic* Participant::register_topic(const std::string& name, TypeSupport type) {
  if (type.register_type(participant_) != ReturnCode_t::RETCODE_OK) return nullptr;
  Topic* topic = participant_->create_topic(name, type.get_type_name(), TOPIC_QOS_DEFAULT);
  if (topic) topics_[name] = topic;
  return topic;
}

Participant::~Participant() {
  if (participant_) {
    participant_->delete_contained_entities();
    DomainParticipantFactory::get_instance()->delete_participant(participant_);
  }
}

}  // namespace cairn::dds
