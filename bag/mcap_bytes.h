#pragma once
// MCAP's wire vocabulary (https://mcap.dev/spec, major version 0): opcodes, the magic, and the
// little-endian fields every record is made of. Shared by bag/mcap_writer and bag/mcap_reader.
// Written here rather than taken from a library: no Debian package ships an MCAP implementation,
// and the format is small (the reference TypeScript reader proves ours, tests/bag/).
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace cairn::bag {

inline constexpr uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};

enum class Op : uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kAttachment = 0x09,
  kAttachmentIndex = 0x0A,
  kStatistics = 0x0B,
  kMetadata = 0x0C,
  kMetadataIndex = 0x0D,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

/// The record's name for error messages ("Chunk", "opcode 0x42").
std::string op_name(uint8_t op);

/// CRC-32 (ISO-HDLC, the one zlib computes), continued from `crc`.
uint32_t crc32_update(uint32_t crc, const uint8_t* data, size_t size);

/// Appends little-endian fields to a byte buffer.
class ByteWriter {
 public:
  explicit ByteWriter(std::vector<uint8_t>* out) : out_(out) {}
  void u8(uint8_t v) { out_->push_back(v); }
  void u16(uint16_t v) { le(v, 2); }
  void u32(uint32_t v) { le(v, 4); }
  void u64(uint64_t v) { le(v, 8); }
  void bytes(const uint8_t* data, size_t size) { out_->insert(out_->end(), data, data + size); }
  void str(const std::string& s) {
    u32(uint32_t(s.size()));
    bytes(reinterpret_cast<const uint8_t*>(s.data()), s.size());
  }
  void string_map(const std::map<std::string, std::string>& m);
  /// A Map<uint16, uint64>: channel ids to counts or offsets.
  void id_map(const std::map<uint16_t, uint64_t>& m) {
    u32(uint32_t(m.size() * 10));
    for (const auto& [id, value] : m) {
      u16(id);
      u64(value);
    }
  }
  /// <opcode><uint64 length><content>.
  void record(Op op, const std::vector<uint8_t>& content) {
    u8(uint8_t(op));
    u64(content.size());
    bytes(content.data(), content.size());
  }

 private:
  void le(uint64_t v, int n) {
    for (int i = 0; i < n; ++i) out_->push_back(uint8_t(v >> (8 * i)));
  }
  std::vector<uint8_t>* out_;
};

/// Reads little-endian fields from a byte range; every read past the end fails (returns nullopt)
/// instead of reading on, so a corrupt length can never run off the buffer.
class ByteReader {
 public:
  ByteReader(const uint8_t* data, size_t size) : p_(data), end_(data + size) {}
  size_t remaining() const { return size_t(end_ - p_); }
  const uint8_t* position() const { return p_; }
  std::optional<uint8_t> u8() { return le<uint8_t>(1); }
  std::optional<uint16_t> u16() { return le<uint16_t>(2); }
  std::optional<uint32_t> u32() { return le<uint32_t>(4); }
  std::optional<uint64_t> u64() { return le<uint64_t>(8); }
  std::optional<std::string> str() {
    auto n = u32();
    if (!n || *n > remaining()) return std::nullopt;
    std::string s(reinterpret_cast<const char*>(p_), *n);
    p_ += *n;
    return s;
  }
  /// `size` bytes, or nullopt when fewer remain.
  const uint8_t* take(uint64_t size) {
    if (size > remaining()) return nullptr;
    const uint8_t* at = p_;
    p_ += size;
    return at;
  }
  std::optional<std::map<std::string, std::string>> string_map();

 private:
  template <typename T>
  std::optional<T> le(int n) {
    if (remaining() < size_t(n)) return std::nullopt;
    uint64_t v = 0;
    for (int i = 0; i < n; ++i) v |= uint64_t(p_[i]) << (8 * i);
    p_ += n;
    return T(v);
  }
  const uint8_t* p_;
  const uint8_t* end_;
};

}  // namespace cairn::bag
