#pragma once
// Reads an MCAP file front to back (https://mcap.dev/spec), one message at a time, so a recording
// of any length replays in bounded memory; and reads its summary (statistics, chunk indexes) from
// the footer without scanning. Damage is named, never fatal: a chunk whose CRC or compression is
// bad is skipped with its byte offset in problems() and reading goes on at the next record; a
// length that runs past the end (a truncated file, a flipped bit) ends reading there, keeping
// every message before it. Pure: reads the std::istream it is given (seekable), never throws on
// content, no printing.
#include <cstdint>
#include <deque>
#include <istream>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace cairn::bag {

struct McapSchema {
  uint16_t id = 0;
  std::string name, encoding, data;
};
struct McapChannel {
  uint16_t id = 0, schema_id = 0;
  std::string topic, message_encoding;
  std::map<std::string, std::string> metadata;
};
struct McapMessage {
  uint16_t channel_id = 0;
  uint32_t sequence = 0;
  uint64_t log_time_ns = 0, publish_time_ns = 0;
  std::vector<uint8_t> data;
};

struct McapReadOptions {
  uint64_t max_chunk_bytes = 1ull << 30;  ///< an uncompressed chunk larger than this is refused as corrupt
};

class McapReader {
 public:
  explicit McapReader(std::istream& in, const McapReadOptions& options = {});

  /// The next message in file order; false at the end of the data (see problems() and finished_cleanly()).
  bool next(McapMessage* message);

  const std::string& profile() const { return profile_; }
  const std::string& library() const { return library_; }
  /// Schemas and channels seen so far (all of them once next() returned false).
  const std::map<uint16_t, McapSchema>& schemas() const { return schemas_; }
  const std::map<uint16_t, McapChannel>& channels() const { return channels_; }
  /// Every damage found so far, each naming its byte offset and record.
  const std::vector<std::string>& problems() const { return problems_; }
  /// True when the data section ended with its DataEnd record (the writer closed the file).
  bool finished_cleanly() const { return saw_data_end_; }

 private:
  bool read_record(uint8_t* op, std::vector<uint8_t>* content);
  void take_record(uint8_t op, const uint8_t* data, size_t size, uint64_t at, const char* where);
  void take_chunk(const std::vector<uint8_t>& content, uint64_t at);
  void problem(uint64_t at, const std::string& what);

  std::istream& in_;
  McapReadOptions options_;
  uint64_t size_ = 0, offset_ = 0;
  bool done_ = false, saw_data_end_ = false;
  std::string profile_, library_;
  std::map<uint16_t, McapSchema> schemas_;
  std::map<uint16_t, McapChannel> channels_;
  std::deque<McapMessage> pending_;
  std::vector<std::string> problems_;
};

/// What a file's summary section says: enough to list its topics and seek without a scan.
struct McapChunkIndex {
  uint64_t start_ns = 0, end_ns = 0, offset = 0, length = 0, index_length = 0;
  uint64_t compressed_size = 0, uncompressed_size = 0;
  std::string compression;
  std::map<uint16_t, uint64_t> message_index_offsets;  ///< channel -> file offset of its MessageIndex
};
struct McapSummary {
  std::map<uint16_t, McapSchema> schemas;
  std::map<uint16_t, McapChannel> channels;
  uint64_t message_count = 0;
  uint32_t chunk_count = 0;
  uint64_t start_ns = 0, end_ns = 0;
  std::map<uint16_t, uint64_t> channel_message_counts;
  std::vector<McapChunkIndex> chunk_indexes;
  size_t summary_offset_groups = 0;
};
/// The summary, or nullopt with `error` naming why (no footer: a cut-off file; no summary; a CRC
/// that does not match; a record that does not parse).
std::optional<McapSummary> read_mcap_summary(std::istream& in, std::string* error);

}  // namespace cairn::bag
