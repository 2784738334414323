// MCAP recordings (bag/mcap_reader.h), as cairn_replay reads them: whatever the bytes, the linear
// reader and the summary reader end with named problems, never a crash, a hang or an exception.
// Seeds: small files of our writer (uncompressed and zstd chunks), written at start-up.
#include <fstream>
#include <sstream>

#include "bag/mcap_reader.h"
#include "bag/mcap_writer.h"
#include "fuzz/fuzz_input.h"

namespace {

void write_seed(const std::string& dir, const std::string& name, bool compress) {
  std::ofstream out(dir + "/" + name, std::ios::binary);
  cairn::bag::McapWriterOptions options;
  options.chunk_bytes = 256;
  options.compress = compress;
  cairn::bag::McapWriter w(out, options);
  const uint16_t s = w.add_schema("cairn_msgs::Ack", "omgidl", "struct Ack { long robot_id; };");
  const uint16_t a = w.add_channel("cairn/ack", s, "cdr", {{"k", "v"}});
  const uint16_t b = w.add_channel("cairn/robot0/odometry", s, "cdr");
  for (int i = 0; i < 24; ++i) {
    const std::vector<uint8_t> payload(8 + i, uint8_t(i));
    w.write(i % 2 ? a : b, uint32_t(i), 100 + uint64_t(i), 100 + uint64_t(i), payload.data(), payload.size());
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const std::string dir = cairn::fuzz::seeds_dir(); !dir.empty()) {
    write_seed(dir, "plain.mcap", false);
    write_seed(dir, "zstd.mcap", true);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  std::istringstream in(bytes);
  cairn::bag::McapReader reader(in);
  cairn::bag::McapMessage m;
  while (reader.next(&m)) {
  }
  std::istringstream again(bytes);
  std::string error;
  cairn::bag::read_mcap_summary(again, &error);
  return 0;
}
