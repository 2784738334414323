#include "bag/mcap_reader.h"

#include <cstring>

#include "bag/mcap_bytes.h"
#include "bag/mcap_records.h"
#include "common/scan_codec.h"  // zstd_decompress

namespace cairn::bag {
namespace {

uint64_t stream_size(std::istream& in) {
  in.seekg(0, std::ios::end);
  const auto end = in.tellg();
  in.seekg(0, std::ios::beg);
  return end < 0 ? 0 : uint64_t(end);
}

}  // namespace

McapReader::McapReader(std::istream& in, const McapReadOptions& options) : in_(in), options_(options) {
  size_ = stream_size(in_);
  uint8_t magic[8] = {};
  if (size_ < 8 || !in_.read(reinterpret_cast<char*>(magic), 8) || std::memcmp(magic, kMagic, 8) != 0) {
    problem(0, "not an MCAP file (no \\x89MCAP0 magic)");
    done_ = true;
    return;
  }
  offset_ = 8;
  uint8_t op = 0;
  std::vector<uint8_t> header;
  if (!read_record(&op, &header)) return;
  ByteReader r(header.data(), header.size());
  auto profile = op == uint8_t(Op::kHeader) ? r.str() : std::nullopt;
  auto library = profile ? r.str() : std::nullopt;
  if (!library) {
    problem(8, "the first record is not a whole Header (" + op_name(op) + ")");
    return;
  }
  profile_ = *profile;
  library_ = *library;
}

void McapReader::problem(uint64_t at, const std::string& what) {
  problems_.push_back("offset " + std::to_string(at) + ": " + what);
}

bool McapReader::read_record(uint8_t* op, std::vector<uint8_t>* content) {
  if (done_) return false;
  const uint64_t at = offset_;
  uint8_t head[9];
  if (size_ - offset_ < 9 || !in_.read(reinterpret_cast<char*>(head), 9)) {
    problem(at, "the file ends without a DataEnd record (cut off while recording?)");
    done_ = true;
    return false;
  }
  *op = head[0];
  uint64_t length = 0;
  for (int i = 0; i < 8; ++i) length |= uint64_t(head[1 + i]) << (8 * i);
  if (length > size_ - offset_ - 9) {
    problem(at, op_name(*op) + " record claims " + std::to_string(length) + " bytes but only " +
                    std::to_string(size_ - offset_ - 9) + " remain: truncated or corrupt; reading stops here");
    done_ = true;
    return false;
  }
  content->resize(length);
  in_.read(reinterpret_cast<char*>(content->data()), std::streamsize(length));
  offset_ += 9 + length;
  return bool(in_);
}

void McapReader::take_record(uint8_t op, const uint8_t* data, size_t size, uint64_t at, const char* where) {
  const std::string what = op_name(op) + std::string(where);
  switch (Op(op)) {
    case Op::kSchema: {
      auto s = parse_schema(data, size);
      if (!s || s->id == 0) {
        problem(at, what + " does not parse (or has id 0): ignored");
      } else {
        schemas_[s->id] = std::move(*s);
      }
      return;
    }
    case Op::kChannel: {
      auto c = parse_channel(data, size);
      if (!c) {
        problem(at, what + " does not parse: ignored");
      } else if (c->schema_id != 0 && !schemas_.count(c->schema_id)) {
        problem(at, what + " for " + c->topic + " names schema " + std::to_string(c->schema_id) +
                        ", never defined: its messages are skipped");
      } else {
        channels_[c->id] = std::move(*c);
      }
      return;
    }
    case Op::kMessage: {
      auto m = parse_message(data, size);
      if (!m) {
        problem(at, what + " is shorter than its fields: skipped");
      } else if (!channels_.count(m->channel_id)) {
        problem(at, what + " on channel " + std::to_string(m->channel_id) + ", never defined: skipped");
      } else {
        pending_.push_back(std::move(*m));
      }
      return;
    }
    default:
      return;  // indexes, attachments, metadata, extensions: not needed to replay
  }
}

void McapReader::take_chunk(const std::vector<uint8_t>& content, uint64_t at) {
  ByteReader r(content.data(), content.size());
  r.u64();  // start time
  r.u64();  // end time
  auto uncompressed_size = r.u64();
  auto crc = uncompressed_size ? r.u32() : std::nullopt;
  auto compression = crc ? r.str() : std::nullopt;
  auto records_size = compression ? r.u64() : std::nullopt;
  const uint8_t* records = records_size ? r.take(*records_size) : nullptr;
  if (!records) return problem(at, "Chunk does not parse: skipped");
  if (*uncompressed_size > options_.max_chunk_bytes) {
    return problem(at, "Chunk claims " + std::to_string(*uncompressed_size) + " uncompressed bytes: skipped");
  }
  std::vector<uint8_t> plain;
  if (compression->empty()) {
    plain.assign(records, records + *records_size);
  } else if (*compression == "zstd") {
    std::string error;
    auto unpacked = zstd_decompress(std::vector<uint8_t>(records, records + *records_size), *uncompressed_size, &error);
    if (!unpacked) return problem(at, "Chunk: " + error + ": skipped");
    plain = std::move(*unpacked);
  } else {
    return problem(at, "Chunk compressed with \"" + *compression + "\", which this reader lacks: skipped");
  }
  if (plain.size() != *uncompressed_size) return problem(at, "Chunk size differs from its header: skipped");
  if (*crc != 0 && crc32_update(0, plain.data(), plain.size()) != *crc) {
    return problem(at, "Chunk CRC mismatch (its records are corrupt): skipped");
  }
  ByteReader records_reader(plain.data(), plain.size());
  while (records_reader.remaining() > 0) {
    const uint64_t inner = uint64_t(records_reader.position() - plain.data());
    auto op = records_reader.u8();
    auto length = op ? records_reader.u64() : std::nullopt;
    const uint8_t* body = length ? records_reader.take(*length) : nullptr;
    if (!body) return problem(at, "Chunk record at " + std::to_string(inner) + " runs past the chunk: rest skipped");
    take_record(*op, body, *length, at, " in the Chunk");
  }
}

bool McapReader::next(McapMessage* message) {
  std::vector<uint8_t> content;
  while (pending_.empty()) {
    const uint64_t at = offset_;
    uint8_t op = 0;
    if (!read_record(&op, &content)) return false;
    if (op == uint8_t(Op::kChunk)) {
      take_chunk(content, at);
    } else if (op == uint8_t(Op::kDataEnd)) {
      saw_data_end_ = true;
      done_ = true;  // the summary repeats schemas and channels: nothing more to replay
      return false;
    } else if (op == uint8_t(Op::kHeader) || op == uint8_t(Op::kFooter)) {
      problem(at, op_name(op) + " inside the data section: reading stops here");
      done_ = true;
      return false;
    } else {
      take_record(op, content.data(), content.size(), at, "");
    }
  }
  *message = std::move(pending_.front());
  pending_.pop_front();
  return true;
}

}  // namespace cairn::bag
