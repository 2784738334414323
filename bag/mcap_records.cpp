#include "bag/mcap_records.h"

namespace cairn::bag {

std::optional<std::map<uint16_t, uint64_t>> parse_id_map(ByteReader& r) {
  auto n = r.u32();
  const uint8_t* body = n ? r.take(*n) : nullptr;
  if (!body || *n % 10 != 0) return std::nullopt;
  ByteReader m(body, *n);
  std::map<uint16_t, uint64_t> out;
  while (m.remaining() > 0) {
    const uint16_t id = *m.u16();
    out[id] = *m.u64();
  }
  return out;
}

std::optional<McapSchema> parse_schema(const uint8_t* data, size_t size) {
  ByteReader r(data, size);
  McapSchema s;
  auto id = r.u16();
  auto name = id ? r.str() : std::nullopt;
  auto encoding = name ? r.str() : std::nullopt;
  auto body = encoding ? r.str() : std::nullopt;
  if (!body) return std::nullopt;
  return McapSchema{*id, *name, *encoding, *body};
}

std::optional<McapChannel> parse_channel(const uint8_t* data, size_t size) {
  ByteReader r(data, size);
  auto id = r.u16();
  auto schema = id ? r.u16() : std::nullopt;
  auto topic = schema ? r.str() : std::nullopt;
  auto encoding = topic ? r.str() : std::nullopt;
  auto metadata = encoding ? r.string_map() : std::nullopt;
  if (!metadata) return std::nullopt;
  return McapChannel{*id, *schema, *topic, *encoding, *metadata};
}

std::optional<McapMessage> parse_message(const uint8_t* data, size_t size) {
  ByteReader r(data, size);
  if (r.remaining() < 22) return std::nullopt;
  McapMessage m;
  m.channel_id = *r.u16();
  m.sequence = *r.u32();
  m.log_time_ns = *r.u64();
  m.publish_time_ns = *r.u64();
  m.data.assign(r.position(), r.position() + r.remaining());
  return m;
}

std::optional<McapChunkIndex> parse_chunk_index(const uint8_t* data, size_t size) {
  ByteReader r(data, size);
  if (r.remaining() < 32) return std::nullopt;
  McapChunkIndex c;
  c.start_ns = *r.u64();
  c.end_ns = *r.u64();
  c.offset = *r.u64();
  c.length = *r.u64();
  auto offsets = parse_id_map(r);
  auto index_length = offsets ? r.u64() : std::nullopt;
  auto compression = index_length ? r.str() : std::nullopt;
  auto compressed = compression ? r.u64() : std::nullopt;
  auto uncompressed = compressed ? r.u64() : std::nullopt;
  if (!uncompressed) return std::nullopt;
  c.message_index_offsets = *offsets;
  c.index_length = *index_length;
  c.compression = *compression;
  c.compressed_size = *compressed;
  c.uncompressed_size = *uncompressed;
  return c;
}

bool parse_statistics(const uint8_t* data, size_t size, McapSummary* summary) {
  ByteReader r(data, size);
  if (r.remaining() < 8 + 2 + 4 * 4 + 16) return false;
  summary->message_count = *r.u64();
  r.u16();  // schema count
  r.u32();  // channel count
  r.u32();  // attachments
  r.u32();  // metadata
  summary->chunk_count = *r.u32();
  summary->start_ns = *r.u64();
  summary->end_ns = *r.u64();
  auto counts = parse_id_map(r);
  if (!counts) return false;
  summary->channel_message_counts = *counts;
  return true;
}

}  // namespace cairn::bag
