#include "bag/mcap_bytes.h"

#include <zlib.h>

#include <cstdio>

namespace cairn::bag {

std::string op_name(uint8_t op) {
  static const char* const kNames[] = {"",           "Header",        "Footer",          "Schema",
                                       "Channel",    "Message",       "Chunk",           "MessageIndex",
                                       "ChunkIndex", "Attachment",    "AttachmentIndex", "Statistics",
                                       "Metadata",   "MetadataIndex", "SummaryOffset",   "DataEnd"};
  if (op >= 1 && op <= 0x0F) return kNames[op];
  char buf[24];
  std::snprintf(buf, sizeof buf, "opcode 0x%02x", op);
  return buf;
}

uint32_t crc32_update(uint32_t crc, const uint8_t* data, size_t size) {
  // zlib's crc32 takes uInt lengths: feed large buffers in pieces.
  while (size > 0) {
    const uInt n = uInt(size > (1u << 30) ? (1u << 30) : size);
    crc = uint32_t(::crc32(crc, data, n));
    data += n;
    size -= n;
  }
  return crc;
}

void ByteWriter::string_map(const std::map<std::string, std::string>& m) {
  std::vector<uint8_t> body;
  ByteWriter w(&body);
  for (const auto& [key, value] : m) {
    w.str(key);
    w.str(value);
  }
  u32(uint32_t(body.size()));
  bytes(body.data(), body.size());
}

std::optional<std::map<std::string, std::string>> ByteReader::string_map() {
  auto n = u32();
  const uint8_t* body = n ? take(*n) : nullptr;
  if (!body) return std::nullopt;
  ByteReader r(body, *n);
  std::map<std::string, std::string> m;
  while (r.remaining() > 0) {
    auto key = r.str();
    auto value = key ? r.str() : std::nullopt;
    if (!value) return std::nullopt;
    m[*key] = *value;
  }
  return m;
}

}  // namespace cairn::bag
