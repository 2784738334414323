// Our MCAP against the reference implementation (@mcap/core, run by Node: tests/bag/mcap_check.mjs):
// its indexed and streaming readers read a file our writer made (every CRC, index and count
// checked), and our reader reads a file its writer made. Skips loudly without Node or the npm
// packages (scripts/install_deps.sh installs both).
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "bag/mcap_reader.h"
#include "bag/mcap_writer.h"

namespace cairn::bag {
namespace {

namespace fs = std::filesystem;

const fs::path kChecker = fs::path(CAIRN_SOURCE_DIR) / "tests/bag/mcap_check.mjs";

// Output and exit code of a shell command.
std::pair<int, std::string> run(const std::string& command) {
  std::string out;
  FILE* p = popen((command + " 2>&1").c_str(), "r");
  if (!p) return {-1, ""};
  char buf[512];
  while (fgets(buf, sizeof buf, p)) out += buf;
  const int status = pclose(p);
  return {WEXITSTATUS(status), out};
}

bool have_reference() {
  return run("command -v node").first == 0 && fs::exists(kChecker.parent_path() / "node_modules/@mcap/core");
}

TEST(McapReference, TheReferenceReaderReadsOurFileAndFindsEveryMessage) {
  if (!have_reference()) GTEST_SKIP() << "SKIPPED: node or tests/bag/node_modules missing (scripts/install_deps.sh)";
  const fs::path file = fs::temp_directory_path() / ("cairn_mcap_ours_" + std::to_string(getpid()) + ".mcap");
  {
    std::ofstream out(file, std::ios::binary);
    McapWriterOptions options;
    options.chunk_bytes = 2048;
    McapWriter w(out, options);
    const uint16_t s = w.add_schema("cairn_msgs::RobotStatus", "omgidl", "struct RobotStatus { long robot_id; };");
    const uint16_t a = w.add_channel("cairn/status", s, "cdr");
    const uint16_t b = w.add_channel("cairn/robot0/odometry", s, "cdr", {{"offered_qos_profiles", ""}});
    for (int i = 0; i < 300; ++i) {
      std::vector<uint8_t> payload(16 + i % 40, uint8_t(i * 7));
      w.write(i % 3 ? a : b, uint32_t(i), 5'000'000'000ull + 1000ull * uint64_t(i), 5'000'000'000ull, payload.data(),
              payload.size());
    }
    ASSERT_TRUE(w.close());
  }
  const auto [code, output] = run("node " + kChecker.string() + " check " + file.string() +
                                  " --topic cairn/status --topic cairn/robot0/odometry");
  fs::remove(file);
  EXPECT_EQ(code, 0) << output;
  EXPECT_NE(output.find("\"messages\":300"), std::string::npos) << output;
  EXPECT_NE(output.find("\"cairn/status\":200"), std::string::npos) << output;
}

TEST(McapReference, OurReaderReadsTheReferenceWritersFile) {
  if (!have_reference()) GTEST_SKIP() << "SKIPPED: node or tests/bag/node_modules missing (scripts/install_deps.sh)";
  const fs::path file = fs::temp_directory_path() / ("cairn_mcap_reference_" + std::to_string(getpid()) + ".mcap");
  const auto [code, output] = run("node " + kChecker.string() + " write-reference " + file.string());
  ASSERT_EQ(code, 0) << output;
  std::ifstream in(file, std::ios::binary);
  std::string error;
  auto summary = read_mcap_summary(in, &error);
  ASSERT_TRUE(summary) << error;
  EXPECT_EQ(summary->message_count, 100u);
  EXPECT_EQ(summary->chunk_indexes.size(), summary->chunk_count);
  in.clear();
  McapReader reader(in);
  McapMessage m;
  int n = 0, on_a = 0;
  while (reader.next(&m)) {
    EXPECT_EQ(m.log_time_ns, 1000u + uint64_t(n));
    EXPECT_EQ(m.data, std::vector<uint8_t>(20 + n % 5, uint8_t(n)));
    on_a += reader.channels().at(m.channel_id).topic == "reference/a";
    ++n;
  }
  fs::remove(file);
  EXPECT_TRUE(reader.problems().empty()) << reader.problems().front();
  EXPECT_TRUE(reader.finished_cleanly());
  EXPECT_EQ(reader.profile(), "ros2");
  EXPECT_EQ(n, 100);
  EXPECT_EQ(on_a, 66);
}

}  // namespace
}  // namespace cairn::bag
