#pragma once
// Decoding shared by the DDS-sample and journal harnesses: bytes as a DDS reader or the base's
// journal restore (BaseNode::restore) take them, i.e. CDR into the generated type, then the
// validation every sample goes through (dds::from_msg), or the JSON of an operator's records.
#include <cstdint>
#include <string>
#include <vector>

#include "base_station/console/alert_log.h"
#include "base_station/console/command_api.h"
#include "base_station/core/object_id_registry.h"
#include "base_station/core/robot_sessions.h"
#include "base_station/core/search_controls.h"
#include "base_station/store/journal.h"
#include "cairn_msgsPubSubTypes.h"
#include "dds/cdr.h"
#include "dds/conversions.h"
#include "dds/navigation_conversions.h"

namespace cairn::fuzz {

template <typename PubSubType, typename Msg>
void decode_sample(const std::vector<uint8_t>& bytes) {
  Msg msg;
  std::string error;
  if (dds::from_cdr<PubSubType>(bytes, &msg)) (void)dds::from_msg(msg, &error);
}

inline void decode_status(const std::vector<uint8_t>& bytes) {
  cairn_msgs::RobotStatus msg;
  std::string error;
  if (dds::from_cdr<cairn_msgs::RobotStatusPubSubType>(bytes, &msg)) (void)dds::nav_status_from(msg, &error);
}

/// A journal record's payload as the base restores a record of `kind`.
inline void decode_journal_payload(base::JournalKind kind, const std::vector<uint8_t>& payload) {
  using base::JournalKind;
  const std::string text(payload.begin(), payload.end());
  std::string error;
  switch (kind) {
    case JournalKind::kKeyframe:
      decode_sample<cairn_msgs::KeyframePubSubType, cairn_msgs::Keyframe>(payload);
      break;
    case JournalKind::kObject:
      decode_sample<cairn_msgs::ObjectReportPubSubType, cairn_msgs::ObjectReport>(payload);
      break;
    case JournalKind::kKeyframePoses:
      decode_sample<cairn_msgs::KeyframePosesPubSubType, cairn_msgs::KeyframePoses>(payload);
      break;
    case JournalKind::kStatus:
      decode_status(payload);
      break;
    case JournalKind::kCommand:
      (void)base::command_record_from_json(text, &error);
      break;
    case JournalKind::kVerdict:
      (void)base::verdict_record_from_json(text, &error);
      break;
    case JournalKind::kSession:
      (void)base::session_record_from_json(text, &error);
      break;
    case JournalKind::kAlertAck:
      (void)base::alert_ack_from_json(text, &error);
      break;
    case JournalKind::kObjectId:
      if (const auto entry = base::object_id_record_from_json(payload, &error)) {
        base::ObjectIdRegistry registry;
        (void)registry.restore(*entry);
      }
      break;
    case JournalKind::kSearch:
      if (const auto record = base::search_record_from_json(text, &error)) {
        base::SearchControls controls;
        (void)controls.restore(*record, &error);
      }
      break;
    case JournalKind::kAlignment:
      (void)base::alignment_request_from_json(text, &error);
      break;
  }
}

}  // namespace cairn::fuzz
