#pragma once
// A DDS sample as the bytes it travels in (CDR, with its encapsulation), and back: what the base
// station's journal stores, so a restored sample goes through the same validation
// (dds::from_msg) as a live one.
#include <fastdds/rtps/common/SerializedPayload.h>

#include <cstdint>
#include <cstring>
#include <vector>

namespace cairn::dds {

template <typename PubSubType, typename Msg>
std::vector<uint8_t> to_cdr(const Msg& msg) {
  PubSubType type;
  Msg copy = msg;  // the generated API takes non-const pointers
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(&copy)());
  if (!type.serialize(&copy, &payload)) return {};
  return std::vector<uint8_t>(payload.data, payload.data + payload.length);
}

/// False when the bytes are not a whole sample of this type (truncated, corrupt, absurd lengths).
template <typename PubSubType, typename Msg>
bool from_cdr(const std::vector<uint8_t>& bytes, Msg* msg) {
  if (bytes.size() < 4) return false;  // not even an encapsulation header
  PubSubType type;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(uint32_t(bytes.size()));
  std::memcpy(payload.data, bytes.data(), bytes.size());
  payload.length = uint32_t(bytes.size());
  try {  // fastcdr throws on lengths past the buffer; a corrupt length can also fail to allocate
    return type.deserialize(&payload, msg);
  } catch (...) {
    return false;
  }
}

}  // namespace cairn::dds
