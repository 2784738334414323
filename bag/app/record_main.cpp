// cairn_record: every Cairn DDS topic (or those --topics names) to an MCAP file, the storage
// format of ROS 2 bags, until Ctrl-C/SIGTERM or --duration. Data flow: one TopicTap per topic
// (bag/app/topic_bag.h) -> samples of each poll ordered by reception time -> McapWriter.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <fstream>
#include <map>
#include <thread>

#include "bag/app/topic_bag.h"
#include "bag/mcap_writer.h"
#include "common/logging.h"

namespace {
std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop = true; }
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Cairn recorder: DDS topics to an MCAP file (ROS 2 bag storage)"};
  cairn::dds::ParticipantOptions po;
  po.name = "cairn_record";
  std::string out_path, log_level = "info";
  int robots = 8;
  double duration_s = 0;
  std::vector<std::string> topics;
  cairn::bag::McapWriterOptions writer_options;
  app.add_option("--out", out_path, "the MCAP file to write")->required();
  app.add_option("--domain", po.domain_id, "DDS domain id")->check(CLI::Range(0, 232));
  app.add_option("--peer", po.initial_peers, "IPv4 address of a DDS peer; repeatable");
  app.add_option("--security", po.security_dir, "DDS Security folder (ca.pem, cert.pem, key.pem)");
  app.add_option("--robots", robots, "record the per-robot topics of robots 0..N-1")->check(CLI::Range(0, 1000));
  app.add_option("--topics", topics, "record only topics whose name contains one of these (e.g. keyframe status)");
  app.add_option("--duration", duration_s, "stop after this many seconds (0 = at Ctrl-C or SIGTERM)");
  app.add_option("--chunk-bytes", writer_options.chunk_bytes, "uncompressed chunk size in bytes")
      ->check(CLI::Range(1024, 1 << 28));
  bool ros2 = false;
  app.add_flag("--ros2", ros2,
               "also the ROS 2 topics: a base's with --ros2 (map, tf, paths, objects) and each ROS 2 robot's under "
               "namespace robotN (scan, odom, cmd_vel)");
  bool ros2_reliable = false;
  app.add_flag("--ros2-reliable", ros2_reliable,
               "reliable robots' scan and odometry taps: nothing lost, but only reliable publishers match "
               "(cairn_replay)");
  app.add_option("--log-level", log_level);
  CLI11_PARSE(app, argc, argv);
  cairn::set_log_level(log_level);
  auto log = cairn::make_logger("record");

  std::ofstream file(out_path, std::ios::binary | std::ios::trunc);
  if (!file) {
    log->error("{}: cannot be written", out_path);
    return 2;
  }
  std::string error;
  auto participant = cairn::dds::Participant::create(po, &error);
  if (!participant) {
    log->error("{}", error);
    return 3;
  }
  auto taps = cairn::bag::make_taps(*participant, robots,
                                    [&](const std::string& t) { return cairn::bag::topic_wanted(t, topics); });
  if (ros2) {
    for (auto& tap : cairn::bag::make_ros2_taps(*participant, robots, ros2_reliable)) {
      if (cairn::bag::topic_wanted(tap->topic(), topics)) taps.push_back(std::move(tap));
    }
  }
  cairn::bag::McapWriter writer(file, writer_options);
  std::map<std::string, uint16_t> schema_of_type;
  std::vector<uint16_t> channel_of_tap;
  std::vector<uint32_t> sequence(taps.size(), 0);
  for (const auto& tap : taps) {
    auto [it, added] = schema_of_type.emplace(tap->type_name(), 0);
    if (added) it->second = writer.add_schema(tap->type_name(), tap->schema_encoding(), tap->schema_text());
    channel_of_tap.push_back(writer.add_channel(tap->topic(), it->second, "cdr"));
  }
  log->info("recording {} topics to {}", taps.size(), out_path);

  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  const auto start = std::chrono::steady_clock::now();
  struct Pending {
    int64_t received_ns;
    size_t tap;
    std::vector<uint8_t> cdr;
  };
  bool last_poll = false;
  while (!last_poll) {
    last_poll = g_stop || (duration_s > 0 &&
                           std::chrono::steady_clock::now() - start > std::chrono::duration<double>(duration_s));
    std::vector<Pending> batch;
    for (size_t i = 0; i < taps.size(); ++i) {
      for (auto& s : taps[i]->take()) batch.push_back({s.received_ns, i, std::move(s.cdr)});
    }
    std::stable_sort(batch.begin(), batch.end(),
                     [](const Pending& a, const Pending& b) { return a.received_ns < b.received_ns; });
    for (const Pending& p : batch) {
      if (p.cdr.empty()) continue;  // a sample that could not be serialised again (never seen)
      writer.write(channel_of_tap[p.tap], sequence[p.tap]++, uint64_t(p.received_ns), uint64_t(p.received_ns),
                   p.cdr.data(), p.cdr.size());
    }
    if (!last_poll) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  const bool ok = writer.close();
  const auto& stats = writer.stats();
  const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!ok) {
    log->error("{}: writing failed (disk full?)", out_path);
    return 4;
  }
  log->info("{} messages ({:.1f} MB of samples) in {:.0f} s -> {} ({:.1f} MB, {} chunks)", stats.messages,
            double(stats.message_bytes) / 1e6, elapsed_s, out_path, double(stats.file_bytes) / 1e6, stats.chunks);
  return 0;
}
