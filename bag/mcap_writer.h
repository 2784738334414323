#pragma once
// Writes an MCAP file (https://mcap.dev/spec): schemas, channels and messages go into chunks
// (zstd-compressed, CRC-checked), each chunk followed by one message index per channel; close()
// writes the summary (schemas, channels, statistics, chunk indexes), the summary offsets and the
// footer, so readers can seek by time and list topics without scanning the file. A file cut off
// before close() (a crash, a pulled battery) still reads linearly up to its last whole chunk.
// Pure: writes to the std::ostream it is given; no threads, no clocks, no printing.
#include <cstdint>
#include <map>
#include <ostream>
#include <string>
#include <vector>

namespace cairn::bag {

struct McapWriterOptions {
  std::string profile = "ros2";  ///< https://mcap.dev/spec/registry: CDR messages, ROS 2 conventions
  std::string library = "cairn";
  size_t chunk_bytes = 1u << 20;  ///< a chunk is closed once its uncompressed records pass this
  bool compress = true;           ///< zstd chunks ("" when false)
  int zstd_level = 3;
};

struct McapWriteStats {
  uint64_t messages = 0;
  uint32_t chunks = 0;
  uint64_t message_bytes = 0;  ///< payload bytes handed to write()
  uint64_t file_bytes = 0;     ///< bytes written to the stream so far
};

class McapWriter {
 public:
  /// Writes the magic and the header at once.
  McapWriter(std::ostream& out, const McapWriterOptions& options = {});
  ~McapWriter();
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  /// A schema's id (1, 2, ...). `encoding`: "ros2msg", "omgidl", ...; `data`: the definition text.
  uint16_t add_schema(const std::string& name, const std::string& encoding, const std::string& data);
  /// A channel's id (0, 1, ...) on `topic` with messages of `schema_id`, encoded as `message_encoding`.
  uint16_t add_channel(const std::string& topic, uint16_t schema_id, const std::string& message_encoding,
                       const std::map<std::string, std::string>& metadata = {});
  /// Appends one message. False (and nothing written) for an unknown channel or after close().
  bool write(uint16_t channel_id, uint32_t sequence, uint64_t log_time_ns, uint64_t publish_time_ns,
             const uint8_t* data, size_t size);
  /// Flushes the open chunk and writes the summary and footer. Idempotent; false when the stream failed.
  bool close();

  const McapWriteStats& stats() const { return stats_; }

 private:
  struct Schema {
    uint16_t id;
    std::string name, encoding, data;
  };
  struct Channel {
    uint16_t id, schema_id;
    std::string topic, message_encoding;
    std::map<std::string, std::string> metadata;
  };
  struct ChunkIndex {
    uint64_t start_ns, end_ns, offset, length, index_length, compressed_size, uncompressed_size;
    std::map<uint16_t, uint64_t> index_offsets;
    std::string compression;
  };
  /// The records' contents (in a chunk, and again in the summary).
  static std::vector<uint8_t> content(const Schema& schema);
  static std::vector<uint8_t> content(const Channel& channel);
  void emit(const std::vector<uint8_t>& bytes);
  void flush_chunk();
  std::vector<uint8_t> summary_records(uint64_t summary_start, std::vector<uint8_t>* offsets) const;

  std::ostream& out_;
  McapWriterOptions options_;
  bool closed_ = false;
  uint64_t offset_ = 0;    ///< bytes written so far
  uint32_t data_crc_ = 0;  ///< CRC of everything before the DataEnd record
  std::vector<Schema> schemas_;
  std::vector<Channel> channels_;
  std::map<uint16_t, uint64_t> channel_counts_;
  uint64_t start_ns_ = 0, end_ns_ = 0;
  // The open chunk: its uncompressed records and, per channel, (log time, offset in the records).
  std::vector<uint8_t> chunk_;
  std::map<uint16_t, std::vector<std::pair<uint64_t, uint64_t>>> chunk_index_;
  uint64_t chunk_start_ns_ = 0, chunk_end_ns_ = 0;
  bool chunk_has_messages_ = false;
  std::vector<ChunkIndex> chunk_indexes_;
  McapWriteStats stats_;
};

}  // namespace cairn::bag
