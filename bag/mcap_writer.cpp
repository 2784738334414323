#include "bag/mcap_writer.h"

#include <algorithm>
#include <stdexcept>

#include "bag/mcap_bytes.h"
#include "common/scan_codec.h"  // zstd_compress

namespace cairn::bag {

McapWriter::McapWriter(std::ostream& out, const McapWriterOptions& options) : out_(out), options_(options) {
  if (options_.chunk_bytes == 0) throw std::invalid_argument("McapWriter: chunk_bytes must be > 0");
  std::vector<uint8_t> bytes(kMagic, kMagic + 8);
  std::vector<uint8_t> header;
  ByteWriter h(&header);
  h.str(options_.profile);
  h.str(options_.library);
  ByteWriter(&bytes).record(Op::kHeader, header);
  emit(bytes);
}

McapWriter::~McapWriter() { close(); }

void McapWriter::emit(const std::vector<uint8_t>& bytes) {
  out_.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  data_crc_ = crc32_update(data_crc_, bytes.data(), bytes.size());
  offset_ += bytes.size();
  stats_.file_bytes = offset_;
}

std::vector<uint8_t> McapWriter::content(const Schema& s) {
  std::vector<uint8_t> out;
  ByteWriter w(&out);
  w.u16(s.id);
  w.str(s.name);
  w.str(s.encoding);
  w.str(s.data);  // uint32 length-prefixed bytes: the same layout as a string
  return out;
}

std::vector<uint8_t> McapWriter::content(const Channel& c) {
  std::vector<uint8_t> out;
  ByteWriter w(&out);
  w.u16(c.id);
  w.u16(c.schema_id);
  w.str(c.topic);
  w.str(c.message_encoding);
  w.string_map(c.metadata);
  return out;
}

uint16_t McapWriter::add_schema(const std::string& name, const std::string& encoding, const std::string& data) {
  if (schemas_.size() >= 0xFFFE) throw std::length_error("McapWriter: more than 65534 schemas");
  schemas_.push_back({uint16_t(schemas_.size() + 1), name, encoding, data});  // id 0 means "no schema"
  ByteWriter(&chunk_).record(Op::kSchema, content(schemas_.back()));
  return schemas_.back().id;
}

uint16_t McapWriter::add_channel(const std::string& topic, uint16_t schema_id, const std::string& message_encoding,
                                 const std::map<std::string, std::string>& metadata) {
  if (schema_id > schemas_.size()) throw std::invalid_argument("McapWriter: channel " + topic + ": unknown schema");
  if (channels_.size() >= 0xFFFF) throw std::length_error("McapWriter: more than 65535 channels");
  channels_.push_back({uint16_t(channels_.size()), schema_id, topic, message_encoding, metadata});
  ByteWriter(&chunk_).record(Op::kChannel, content(channels_.back()));
  return channels_.back().id;
}

bool McapWriter::write(uint16_t channel_id, uint32_t sequence, uint64_t log_time_ns, uint64_t publish_time_ns,
                       const uint8_t* data, size_t size) {
  if (closed_ || channel_id >= channels_.size()) return false;
  chunk_index_[channel_id].emplace_back(log_time_ns, chunk_.size());
  ByteWriter w(&chunk_);
  w.u8(uint8_t(Op::kMessage));
  w.u64(2 + 4 + 8 + 8 + size);
  w.u16(channel_id);
  w.u32(sequence);
  w.u64(log_time_ns);
  w.u64(publish_time_ns);
  w.bytes(data, size);
  chunk_start_ns_ = chunk_has_messages_ ? std::min(chunk_start_ns_, log_time_ns) : log_time_ns;
  chunk_end_ns_ = chunk_has_messages_ ? std::max(chunk_end_ns_, log_time_ns) : log_time_ns;
  start_ns_ = stats_.messages ? std::min(start_ns_, log_time_ns) : log_time_ns;
  end_ns_ = stats_.messages ? std::max(end_ns_, log_time_ns) : log_time_ns;
  chunk_has_messages_ = true;
  ++channel_counts_[channel_id];
  ++stats_.messages;
  stats_.message_bytes += size;
  if (chunk_.size() >= options_.chunk_bytes) flush_chunk();
  return bool(out_);
}

void McapWriter::flush_chunk() {
  if (chunk_.empty()) return;
  std::vector<uint8_t> records = chunk_;
  std::string compression;
  if (options_.compress) {
    auto packed = zstd_compress(chunk_.data(), chunk_.size(), options_.zstd_level);
    if (!packed.empty()) {
      records = std::move(packed);
      compression = "zstd";
    }
  }
  std::vector<uint8_t> content;
  ByteWriter c(&content);
  c.u64(chunk_has_messages_ ? chunk_start_ns_ : 0);
  c.u64(chunk_has_messages_ ? chunk_end_ns_ : 0);
  c.u64(chunk_.size());
  c.u32(crc32_update(0, chunk_.data(), chunk_.size()));
  c.str(compression);
  c.u64(records.size());
  c.bytes(records.data(), records.size());

  ChunkIndex index{chunk_has_messages_ ? chunk_start_ns_ : 0,
                   chunk_has_messages_ ? chunk_end_ns_ : 0,
                   offset_,
                   1 + 8 + content.size(),
                   0,
                   records.size(),
                   chunk_.size(),
                   {},
                   compression};
  std::vector<uint8_t> bytes;
  ByteWriter(&bytes).record(Op::kChunk, content);
  for (const auto& [channel, entries] : chunk_index_) {
    index.index_offsets[channel] = offset_ + bytes.size();
    std::vector<uint8_t> mi;
    ByteWriter m(&mi);
    m.u16(channel);
    m.u32(uint32_t(entries.size() * 16));
    for (const auto& [time_ns, at] : entries) {
      m.u64(time_ns);
      m.u64(at);
    }
    ByteWriter(&bytes).record(Op::kMessageIndex, mi);
  }
  index.index_length = offset_ + bytes.size() - (index.offset + index.length);
  emit(bytes);
  chunk_indexes_.push_back(index);
  ++stats_.chunks;
  chunk_.clear();
  chunk_index_.clear();
  chunk_has_messages_ = false;
}

std::vector<uint8_t> McapWriter::summary_records(uint64_t summary_start, std::vector<uint8_t>* offsets) const {
  std::vector<uint8_t> out;
  ByteWriter w(&out);
  auto group = [&](Op op, const auto& write_records) {
    const size_t start = out.size();
    write_records();
    if (out.size() == start) return;
    std::vector<uint8_t> so;
    ByteWriter s(&so);
    s.u8(uint8_t(op));
    s.u64(summary_start + start);
    s.u64(out.size() - start);
    ByteWriter(offsets).record(Op::kSummaryOffset, so);
  };
  group(Op::kSchema, [&] {
    for (const auto& s : schemas_) w.record(Op::kSchema, content(s));
  });
  group(Op::kChannel, [&] {
    for (const auto& c : channels_) w.record(Op::kChannel, content(c));
  });
  group(Op::kStatistics, [&] {
    std::vector<uint8_t> c;
    ByteWriter r(&c);
    r.u64(stats_.messages);
    r.u16(uint16_t(schemas_.size()));
    r.u32(uint32_t(channels_.size()));
    r.u32(0);  // attachments
    r.u32(0);  // metadata
    r.u32(stats_.chunks);
    r.u64(stats_.messages ? start_ns_ : 0);
    r.u64(stats_.messages ? end_ns_ : 0);
    r.id_map(channel_counts_);
    w.record(Op::kStatistics, c);
  });
  group(Op::kChunkIndex, [&] {
    for (const auto& ci : chunk_indexes_) {
      std::vector<uint8_t> c;
      ByteWriter r(&c);
      r.u64(ci.start_ns);
      r.u64(ci.end_ns);
      r.u64(ci.offset);
      r.u64(ci.length);
      r.id_map(ci.index_offsets);
      r.u64(ci.index_length);
      r.str(ci.compression);
      r.u64(ci.compressed_size);
      r.u64(ci.uncompressed_size);
      w.record(Op::kChunkIndex, c);
    }
  });
  return out;
}

bool McapWriter::close() {
  if (closed_) return bool(out_);
  flush_chunk();
  closed_ = true;
  std::vector<uint8_t> data_end;
  ByteWriter d(&data_end);
  std::vector<uint8_t> crc;
  ByteWriter(&crc).u32(data_crc_);
  d.record(Op::kDataEnd, crc);
  emit(data_end);

  const uint64_t summary_start = offset_;
  std::vector<uint8_t> offsets;
  std::vector<uint8_t> tail = summary_records(summary_start, &offsets);
  const uint64_t summary_offset_start = summary_start + tail.size();
  tail.insert(tail.end(), offsets.begin(), offsets.end());
  // Footer: its summary CRC covers the summary, the offsets and the footer up to the CRC field.
  ByteWriter f(&tail);
  f.u8(uint8_t(Op::kFooter));
  f.u64(8 + 8 + 4);
  f.u64(summary_start);
  f.u64(summary_offset_start);
  f.u32(crc32_update(0, tail.data(), tail.size()));
  f.bytes(kMagic, 8);
  emit(tail);
  out_.flush();
  return bool(out_);
}

}  // namespace cairn::bag
