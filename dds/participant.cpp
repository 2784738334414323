#include "dds/participant.h"

#include <algorithm>

#include "dds/qos.h"

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

  // Unicast discovery: loopback (port left open: the transport probes max_initial_peers_range ids)
  // plus the configured peers, each probed at the ports of its first few participant ids only.
  auto& builtin = qos.wire_protocol().builtin;
  Locator_t loopback;
  IPLocator::setIPv4(loopback, "127.0.0.1");
  loopback.kind = LOCATOR_KIND_UDPv4;
  builtin.initialPeersList.push_back(loopback);
  for (const auto& address : options.initial_peers) {
    Locator_t locator;
    if (!IPLocator::setIPv4(locator, address)) {
      if (error) *error = "invalid initial peer address '" + address + "'";
      return nullptr;
    }
    locator.kind = LOCATOR_KIND_UDPv4;
    for (uint32_t id = 0; id < options.remote_peer_participants; ++id) {
      locator.port = qos.wire_protocol().port.getUnicastPort(uint32_t(options.domain_id), id);
      builtin.initialPeersList.push_back(locator);
    }
  }
  if (!(options.announcement_period_s > 0) || !(options.lease_duration_s > 2 * options.announcement_period_s)) {
    if (error) *error = "the participant lease must be longer than two announcement periods";
    return nullptr;
  }
  builtin.discovery_config.leaseDuration_announcementperiod = to_duration(options.announcement_period_s);
  builtin.discovery_config.leaseDuration = to_duration(options.lease_duration_s);
  // Under DDS Security the GUID prefix is derived from the certificate (PKI-DH), not the host, so
  // Fast DDS could not tell hosts apart and would ignore every peer: the filter is left off.
  if (options.same_host_only && options.security_dir.empty()) {
    builtin.discovery_config.ignoreParticipantFlags =
        eprosima::fastrtps::rtps::ParticipantFilteringFlags::FILTER_DIFFERENT_HOST;
  }
  // No Cairn topic uses the liveliness QoS (writers stay AUTOMATIC with an infinite lease), so the
  // writer liveliness protocol's reliable builtin endpoints only cost heartbeats and
  // acknowledgements, a third of the discovery traffic on a slow radio.
  builtin.use_WriterLivelinessProtocol = false;

  if (options.link_budget_bytes_per_sec > 0) {
    // Fast DDS cuts samples into fragments no larger than a period's bytes: a keyframe cut into
    // 390-byte pieces (50 ms periods) cost a NACK_FRAG storm; kLinkPeriodBytes keeps it whole.
    auto flow = std::make_shared<eprosima::fastdds::rtps::FlowControllerDescriptor>();
    flow->name = kLinkFlowController;
    flow->scheduler = eprosima::fastdds::rtps::FlowControllerSchedulerPolicy::HIGH_PRIORITY;
    flow->max_bytes_per_period = int32_t(kLinkPeriodBytes);
    flow->period_ms = std::max<uint64_t>(10, uint64_t(1000.0 * kLinkPeriodBytes / options.link_budget_bytes_per_sec));
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
