// The MCAP writer and reader against each other, the summary's indexes against the bytes they
// point to, and damaged files (truncations, flipped bits, unknown records) read without a crash,
// each damage named. The reference implementation's view of our files: tests/bag/mcap_check.mjs.
#include <gtest/gtest.h>

#include <sstream>

#include "bag/mcap_bytes.h"
#include "bag/mcap_reader.h"
#include "bag/mcap_writer.h"

namespace cairn::bag {
namespace {

// A file of `n` messages alternating over two channels, in chunks of ~`chunk_bytes`.
std::string make_file(int n, size_t chunk_bytes = 1u << 20, bool compress = true) {
  std::ostringstream out;
  McapWriterOptions options;
  options.chunk_bytes = chunk_bytes;
  options.compress = compress;
  McapWriter w(out, options);
  const uint16_t s = w.add_schema("cairn_msgs::Odometry", "omgidl", "struct Odometry { double x; };");
  const uint16_t a = w.add_channel("cairn/robot0/odometry", s, "cdr", {{"robot", "0"}});
  const uint16_t b = w.add_channel("cairn/robot1/odometry", s, "cdr");
  for (int i = 0; i < n; ++i) {
    std::vector<uint8_t> payload(40 + i % 7, uint8_t(i));
    EXPECT_TRUE(w.write(i % 2 ? b : a, uint32_t(i), 1000 + 10 * uint64_t(i), 999 + 10 * uint64_t(i), payload.data(),
                        payload.size()));
  }
  EXPECT_TRUE(w.close());
  return out.str();
}

// Everything a reader gives for `bytes`.
struct Read {
  std::vector<McapMessage> messages;
  std::vector<std::string> problems;
  bool clean = false;
  std::string profile;
  std::map<uint16_t, McapChannel> channels;
  std::map<uint16_t, McapSchema> schemas;
};
Read read_all(const std::string& bytes) {
  std::istringstream in(bytes);
  McapReader reader(in);
  Read out;
  McapMessage m;
  while (reader.next(&m)) out.messages.push_back(m);
  out.problems = reader.problems();
  out.clean = reader.finished_cleanly();
  out.profile = reader.profile();
  out.channels = reader.channels();
  out.schemas = reader.schemas();
  return out;
}

TEST(Mcap, WhatIsWrittenIsReadBackInOrderWithItsChannelsAndSchemas) {
  for (bool compress : {true, false}) {
    const std::string file = make_file(500, 4096, compress);
    const Read read = read_all(file);
    const auto& messages = read.messages;
    ASSERT_EQ(messages.size(), 500u);
    EXPECT_TRUE(read.problems.empty()) << read.problems.front();
    EXPECT_TRUE(read.clean);
    EXPECT_EQ(read.profile, "ros2");
    ASSERT_EQ(read.channels.size(), 2u);
    EXPECT_EQ(read.channels.at(0).topic, "cairn/robot0/odometry");
    EXPECT_EQ(read.channels.at(0).metadata.at("robot"), "0");
    EXPECT_EQ(read.schemas.at(1).encoding, "omgidl");
    for (int i = 0; i < 500; ++i) {
      EXPECT_EQ(messages[i].channel_id, i % 2);
      EXPECT_EQ(messages[i].sequence, uint32_t(i));
      EXPECT_EQ(messages[i].log_time_ns, 1000 + 10 * uint64_t(i));
      EXPECT_EQ(messages[i].publish_time_ns, 999 + 10 * uint64_t(i));
      EXPECT_EQ(messages[i].data, std::vector<uint8_t>(40 + i % 7, uint8_t(i)));
    }
  }
}

TEST(Mcap, TheSummaryCountsEverythingAndItsIndexesPointAtTheirRecords) {
  const std::string file = make_file(500, 4096);
  std::istringstream in(file);
  std::string error;
  auto summary = read_mcap_summary(in, &error);
  ASSERT_TRUE(summary) << error;
  EXPECT_EQ(summary->message_count, 500u);
  EXPECT_EQ(summary->channel_message_counts.at(0), 250u);
  EXPECT_EQ(summary->channel_message_counts.at(1), 250u);
  EXPECT_EQ(summary->start_ns, 1000u);
  EXPECT_EQ(summary->end_ns, 1000u + 10 * 499);
  EXPECT_EQ(summary->channels.size(), 2u);
  EXPECT_EQ(summary->schemas.size(), 1u);
  EXPECT_EQ(summary->summary_offset_groups, 4u);  // schemas, channels, statistics, chunk indexes
  ASSERT_GT(summary->chunk_count, 3u);
  ASSERT_EQ(summary->chunk_indexes.size(), summary->chunk_count);
  uint64_t previous_end = 0;
  for (const auto& ci : summary->chunk_indexes) {
    EXPECT_EQ(uint8_t(file[ci.offset]), uint8_t(Op::kChunk));
    EXPECT_EQ(ci.compression, "zstd");
    EXPECT_GE(ci.start_ns, previous_end);
    previous_end = ci.end_ns;
    uint64_t index_bytes = 0;
    for (const auto& [channel, at] : ci.message_index_offsets) {
      ASSERT_LT(at, file.size());
      EXPECT_EQ(uint8_t(file[at]), uint8_t(Op::kMessageIndex));
      ByteReader r(reinterpret_cast<const uint8_t*>(file.data()) + at + 1, 8 + 2);
      index_bytes += 9 + *r.u64();
      EXPECT_EQ(*r.u16(), channel);
    }
    EXPECT_EQ(index_bytes, ci.index_length);
    EXPECT_EQ(ci.offset + ci.length, ci.message_index_offsets.begin()->second);
  }
}

TEST(Mcap, ATruncatedFileKeepsEveryWholeChunkAndSaysWhereItWasCut) {
  const std::string file = make_file(500, 4096);
  std::istringstream whole(file);
  std::string error;
  auto summary = read_mcap_summary(whole, &error);
  ASSERT_TRUE(summary);
  // Cut in the middle of the third chunk: the first two chunks' messages survive.
  const auto& third = summary->chunk_indexes[2];
  const std::string cut = file.substr(0, third.offset + third.length / 2);
  const Read read = read_all(cut);
  size_t before = 0;
  for (const auto& m : read.messages) before += m.log_time_ns < third.start_ns;
  EXPECT_EQ(before, read.messages.size());
  EXPECT_GT(read.messages.size(), 0u);
  EXPECT_FALSE(read.clean);
  ASSERT_EQ(read.problems.size(), 1u);
  EXPECT_NE(read.problems[0].find("offset " + std::to_string(third.offset) + ": Chunk record claims"),
            std::string::npos)
      << read.problems[0];
  std::istringstream in(cut);
  EXPECT_FALSE(read_mcap_summary(in, &error));
  EXPECT_NE(error.find("cut off"), std::string::npos) << error;
}

TEST(Mcap, ACorruptChunkIsSkippedAndNamedAndTheRestIsRead) {
  const std::string file = make_file(500, 4096, /*compress=*/false);
  std::istringstream whole(file);
  std::string error;
  auto summary = read_mcap_summary(whole, &error);
  ASSERT_TRUE(summary);
  const auto& second = summary->chunk_indexes[1];
  std::string damaged = file;
  damaged[second.offset + second.length - 5] ^= 0x10;  // a payload byte: only the CRC can tell
  const Read read = read_all(damaged);
  const auto& messages = read.messages;
  EXPECT_TRUE(read.clean);
  ASSERT_EQ(read.problems.size(), 1u);
  EXPECT_EQ(read.problems[0],
            "offset " + std::to_string(second.offset) + ": Chunk CRC mismatch (its records are corrupt): skipped");
  for (const auto& m : messages) EXPECT_FALSE(m.log_time_ns >= second.start_ns && m.log_time_ns <= second.end_ns);
  EXPECT_LT(messages.size(), 500u);
  EXPECT_GT(messages.size(), 400u);
  // The summary's own CRC catches a flipped summary byte.
  std::string bad_summary = file;
  bad_summary[bad_summary.size() - 8 - 29 - 20] ^= 0x01;
  std::istringstream in(bad_summary);
  EXPECT_FALSE(read_mcap_summary(in, &error));
  EXPECT_NE(error.find("summary CRC mismatch"), std::string::npos) << error;
}

TEST(Mcap, UnknownRecordsAreSkippedAndNonMcapInputIsNamed) {
  std::string file = make_file(10);
  // An application record (opcode 0x80, 3 bytes) after the header: readers must skip it.
  const size_t after_header = 8 + 9 + 4 + 4 + 4 + 5;  // magic, record head, "ros2", "cairn"
  std::vector<uint8_t> extension;
  ByteWriter(&extension).record(Op(0x80), {1, 2, 3});
  file.insert(after_header, std::string(extension.begin(), extension.end()));
  const Read read = read_all(file);
  EXPECT_EQ(read.messages.size(), 10u);
  EXPECT_TRUE(read.problems.empty());
  const Read carmen = read_all("#CARMEN log, not MCAP");
  ASSERT_EQ(carmen.problems.size(), 1u);
  EXPECT_NE(carmen.problems[0].find("not an MCAP file"), std::string::npos);
}

TEST(Mcap, EveryTruncationAndEveryFlippedLengthByteReadsWithoutCrashing) {
  const std::string file = make_file(40, 512);
  for (size_t n = 0; n < file.size(); n += 7) read_all(file.substr(0, n));
  for (size_t i = 0; i < file.size(); ++i) {
    std::string damaged = file;
    damaged[i] = char(~damaged[i]);
    EXPECT_LE(read_all(damaged).messages.size(), 40u);  // never more than were written
    std::istringstream in(damaged);
    std::string error;
    read_mcap_summary(in, &error);
  }
}

}  // namespace
}  // namespace cairn::bag
