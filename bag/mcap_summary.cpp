// read_mcap_summary (bag/mcap_reader.h): the footer, then the summary section it points to.
#include <cstring>

#include "bag/mcap_bytes.h"
#include "bag/mcap_reader.h"
#include "bag/mcap_records.h"

namespace cairn::bag {
namespace {

constexpr uint64_t kFooterBytes = 1 + 8 + 8 + 8 + 4;  // opcode, length, summary_start, offset_start, crc

std::optional<McapSummary> fail(std::string* error, const std::string& what) {
  if (error) *error = what;
  return std::nullopt;
}

}  // namespace

std::optional<McapSummary> read_mcap_summary(std::istream& in, std::string* error) {
  in.seekg(0, std::ios::end);
  const auto end = in.tellg();
  if (end < 0 || uint64_t(end) < 8 + kFooterBytes + 8) return fail(error, "too short to hold a footer");
  const uint64_t size = uint64_t(end);
  const uint64_t footer_at = size - 8 - kFooterBytes;
  std::vector<uint8_t> tail(kFooterBytes + 8);
  in.seekg(std::streamoff(footer_at));
  if (!in.read(reinterpret_cast<char*>(tail.data()), std::streamsize(tail.size()))) {
    return fail(error, "the footer cannot be read");
  }
  if (std::memcmp(tail.data() + kFooterBytes, kMagic, 8) != 0 || tail[0] != uint8_t(Op::kFooter)) {
    return fail(error, "no footer and closing magic: the file was cut off before it was closed");
  }
  ByteReader f(tail.data() + 9, kFooterBytes - 9);
  const uint64_t summary_start = *f.u64();
  const uint64_t summary_offset_start = *f.u64();
  const uint32_t summary_crc = *f.u32();
  if (summary_start == 0) return fail(error, "the file has no summary section");
  if (summary_start < 8 || summary_start > footer_at) {
    return fail(error, "the footer's summary_start " + std::to_string(summary_start) + " lies outside the file");
  }
  std::vector<uint8_t> summary(footer_at + 1 + 8 + 16 - summary_start);  // through summary_offset_start
  in.seekg(std::streamoff(summary_start));
  if (!in.read(reinterpret_cast<char*>(summary.data()), std::streamsize(summary.size()))) {
    return fail(error, "the summary section cannot be read");
  }
  if (summary_crc != 0 && crc32_update(0, summary.data(), summary.size()) != summary_crc) {
    return fail(error, "summary CRC mismatch: the summary section is corrupt");
  }
  McapSummary out;
  const uint64_t records_end = footer_at - summary_start;
  ByteReader r(summary.data(), size_t(records_end));
  while (r.remaining() > 0) {
    const uint64_t at = summary_start + uint64_t(r.position() - summary.data());
    auto op = r.u8();
    auto length = op ? r.u64() : std::nullopt;
    const uint8_t* body = length ? r.take(*length) : nullptr;
    if (!body) return fail(error, "offset " + std::to_string(at) + ": a summary record runs past the footer");
    const std::string bad = "offset " + std::to_string(at) + ": " + op_name(*op) + " in the summary does not parse";
    switch (Op(*op)) {
      case Op::kSchema: {
        auto s = parse_schema(body, *length);
        if (!s) return fail(error, bad);
        out.schemas[s->id] = *s;
        break;
      }
      case Op::kChannel: {
        auto c = parse_channel(body, *length);
        if (!c) return fail(error, bad);
        out.channels[c->id] = *c;
        break;
      }
      case Op::kStatistics:
        if (!parse_statistics(body, *length, &out)) return fail(error, bad);
        break;
      case Op::kChunkIndex: {
        auto c = parse_chunk_index(body, *length);
        if (!c) return fail(error, bad);
        out.chunk_indexes.push_back(*c);
        break;
      }
      case Op::kSummaryOffset:
        if (summary_offset_start == 0 || at < summary_offset_start) {
          return fail(error, "offset " + std::to_string(at) + ": a SummaryOffset before the summary offset section");
        }
        ++out.summary_offset_groups;
        break;
      default:
        break;  // attachment and metadata indexes: Cairn writes none
    }
  }
  return out;
}

}  // namespace cairn::bag
