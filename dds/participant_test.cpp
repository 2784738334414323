// The participant's radio settings: which peers discovery probes, the announcement period, and the
// link budget's one flow controller that sends a victim before the keyframes queued ahead of it.
#include "dds/participant.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include <fastrtps/utils/IPLocator.h>
#include <fastrtps/xmlparser/XMLProfileManager.h>

#include "cairn_msgsPubSubTypes.h"
#include "dds/domain_lease.h"
#include "dds/endpoints.h"

namespace cairn::dds {
namespace {

int test_domain() {
  static const std::unique_ptr<DomainLease> lease = DomainLease::claim({}, nullptr);
  return lease ? lease->domain_id() : 0;
}

TEST(Participant, ARemotePeerIsProbedAtItsFirstParticipantsPortsOnly) {
  ParticipantOptions o{test_domain(), "participant_test"};
  o.initial_peers = {"10.1.2.3"};
  o.remote_peer_participants = 3;
  std::string error;
  auto p = Participant::create(o, &error);
  ASSERT_TRUE(p) << error;
  const auto& peers = p->get()->get_qos().wire_protocol().builtin.initialPeersList;
  std::vector<uint32_t> remote_ports;
  int loopback = 0;
  for (const auto& locator : peers) {
    if (eprosima::fastrtps::rtps::IPLocator::toIPv4string(locator) == "10.1.2.3")
      remote_ports.push_back(locator.port);
    else
      ++loopback;
  }
  // Participant ids 0, 1, 2 of the domain's metatraffic unicast ports (7400 + 250 d + 10 + 2 id).
  const uint32_t base = 7400 + 250 * uint32_t(o.domain_id) + 10;
  EXPECT_EQ(remote_ports, (std::vector<uint32_t>{base, base + 2, base + 4}));
  EXPECT_EQ(loopback, 1);  // this host: the transport probes its whole range
}

TEST(Participant, AnnouncementsAndLeaseAreSetAndALeaseTooShortIsRefusedByName) {
  ParticipantOptions o{test_domain(), "participant_test"};
  o.announcement_period_s = kSlowLinkAnnouncementPeriod_s;
  o.lease_duration_s = kSlowLinkLeaseDuration_s;
  std::string error;
  auto p = Participant::create(o, &error);
  ASSERT_TRUE(p) << error;
  const auto& discovery = p->get()->get_qos().wire_protocol().builtin.discovery_config;
  EXPECT_EQ(discovery.leaseDuration_announcementperiod.seconds, 10);
  EXPECT_EQ(discovery.leaseDuration.seconds, 60);

  o.lease_duration_s = 15.0;  // one lost announcement would end the peer
  EXPECT_FALSE(Participant::create(o, &error));
  EXPECT_NE(error.find("lease"), std::string::npos) << error;
}

TEST(Participant, DiscoveryStaysSmallOnASlowRadio) {
  // The simulator's participant ignores other hosts (the base across the radio), no participant
  // runs the writer liveliness protocol, and a reader waits a second before asking a writer it has
  // not heard yet for data (see reader_qos): on a 50 kbit/s radio these decided between nothing
  // delivered and everything (docs/benchmarks.md "The slow radio").
  ParticipantOptions o{test_domain(), "participant_test"};
  o.same_host_only = true;
  std::string error;
  auto p = Participant::create(o, &error);
  ASSERT_TRUE(p) << error;
  const auto& builtin = p->get()->get_qos().wire_protocol().builtin;
  EXPECT_EQ(builtin.discovery_config.ignoreParticipantFlags,
            eprosima::fastrtps::rtps::ParticipantFilteringFlags::FILTER_DIFFERENT_HOST);
  EXPECT_FALSE(builtin.use_WriterLivelinessProtocol);
  o.same_host_only = false;
  auto q = Participant::create(o, &error);
  ASSERT_TRUE(q) << error;
  EXPECT_EQ(q->get()->get_qos().wire_protocol().builtin.discovery_config.ignoreParticipantFlags,
            eprosima::fastrtps::rtps::ParticipantFilteringFlags::NO_FILTER);
  for (TopicKind kind : {TopicKind::kKeyframe, TopicKind::kAck, TopicKind::kGoal, TopicKind::kObject}) {
    EXPECT_GE(reader_qos(kind).reliable_reader_qos().times.initialAcknackDelay.seconds, 1);
  }
}

TEST(Participant, LinkPrioritiesPutAFindFirstAndPoseUpdatesLast) {
  EXPECT_LT(link_priority(TopicKind::kObject), link_priority(TopicKind::kKeyframe));
  EXPECT_LT(link_priority(TopicKind::kKeyframe), link_priority(TopicKind::kKeyframePoses));
  const auto q = writer_qos(TopicKind::kObject, QosOptions{true});
  EXPECT_EQ(q.publish_mode().flow_controller_name, std::string(kLinkFlowController));
  EXPECT_EQ(q.publish_mode().kind, eprosima::fastdds::dds::ASYNCHRONOUS_PUBLISH_MODE);
  const std::string* priority =
      eprosima::fastrtps::rtps::PropertyPolicyHelper::find_property(q.properties(), "fastdds.sfc.priority");
  ASSERT_NE(priority, nullptr);
  EXPECT_EQ(*priority, "-10");
  EXPECT_NE(writer_qos(TopicKind::kObject).publish_mode().flow_controller_name, std::string(kLinkFlowController));
}

TEST(Participant, OnABudgetedLinkAVictimOvertakesTheKeyframesQueuedBeforeIt) {
  // 8 kB/s: twenty 1.2 kB keyframes take about 3 s to leave; the object written after them must
  // arrive before the last of them (priority), and every keyframe must still arrive (nothing lost).
  // Within one process Fast DDS hands samples over directly, past any flow controller: this test
  // turns that off so that they travel as between two robots' processes.
  using eprosima::fastrtps::xmlparser::XMLProfileManager;
  const eprosima::fastrtps::LibrarySettingsAttributes before = XMLProfileManager::library_settings();
  eprosima::fastrtps::LibrarySettingsAttributes through_transport = before;
  through_transport.intraprocess_delivery = eprosima::fastrtps::INTRAPROCESS_OFF;
  XMLProfileManager::library_settings(through_transport);
  struct Restore {
    eprosima::fastrtps::LibrarySettingsAttributes settings;
    ~Restore() { XMLProfileManager::library_settings(settings); }
  } restore{before};
  ParticipantOptions o{test_domain(), "participant_test_robot"};
  o.link_budget_bytes_per_sec = 8000;
  std::string error;
  auto robot = Participant::create(o, &error);
  ASSERT_TRUE(robot) << error;
  auto base = Participant::create({test_domain(), "participant_test_base"}, &error);
  ASSERT_TRUE(base) << error;
  Writer<KeyframeTopic> keyframes_out(*robot, QosOptions{true});
  Writer<ObjectTopic> objects_out(*robot, QosOptions{true});
  Reader<KeyframeTopic> keyframes_in(*base);
  Reader<ObjectTopic> objects_in(*base);
  ASSERT_TRUE(keyframes_out.ok() && objects_out.ok() && keyframes_in.ok() && objects_in.ok());
  const auto matched_by = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while ((keyframes_out.matched_readers() == 0 || objects_out.matched_readers() == 0) &&
         std::chrono::steady_clock::now() < matched_by) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_GT(objects_out.matched_readers(), 0);

  constexpr int kKeyframes = 20;
  for (int i = 0; i < kKeyframes; ++i) {
    cairn_msgs::Keyframe kf;
    kf.robot_id(3);
    kf.seq(i);
    kf.scan_zstd(std::vector<uint8_t>(1000, uint8_t(i)));
    ASSERT_TRUE(keyframes_out.write(kf));
  }
  cairn_msgs::ObjectReport victim;
  victim.robot_id(3);
  victim.object_seq(0);
  victim.class_name("victim");
  ASSERT_TRUE(objects_out.write(victim));

  int keyframes_before_victim = -1, keyframes = 0;
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (keyframes < kKeyframes && std::chrono::steady_clock::now() < end) {
    keyframes += int(keyframes_in.take_all().size());
    if (keyframes_before_victim < 0 && !objects_in.take_all().empty()) keyframes_before_victim = keyframes;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  EXPECT_EQ(keyframes, kKeyframes);
  ASSERT_GE(keyframes_before_victim, 0) << "the victim never arrived";
  EXPECT_LT(keyframes_before_victim, kKeyframes / 2) << "the victim waited behind the keyframes";
}

}  // namespace
}  // namespace cairn::dds
