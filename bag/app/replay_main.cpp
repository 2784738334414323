// cairn_replay FILE: plays an MCAP recording of Cairn topics back onto DDS with its original
// timing (scaled by --speed), so a base station or an agent runs on a recorded mission as it did
// live. Data flow: McapReader (bag/mcap_reader.h) -> one TopicPlayer per channel (decodes the CDR,
// filters by robot, writes) -> DDS. Damage in the file is named and skipped; the rest plays.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <fstream>
#include <map>
#include <thread>

#include "bag/app/topic_bag.h"
#include "bag/mcap_reader.h"
#include "common/logging.h"

namespace {
std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop = true; }
using Clock = std::chrono::steady_clock;

struct ChannelPlay {
  std::unique_ptr<cairn::bag::TopicPlayer> player;  ///< null: not played (named once in the log)
  std::string topic, type_name;
  uint64_t written = 0, filtered = 0, undecodable = 0, failed = 0;
};
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Cairn replay: an MCAP recording back onto DDS"};
  cairn::dds::ParticipantOptions po;
  po.name = "cairn_replay";
  std::string path, log_level = "info";
  double speed = 1.0, wait_s = 3.0;
  int subscribers = 1;
  std::vector<std::string> topics;
  std::vector<int> robots;
  app.add_option("file", path, "the MCAP recording")->required();
  app.add_option("--speed", speed, "times real time (0 = as fast as possible)")->check(CLI::Range(0.0, 1000.0));
  app.add_option("--topics", topics, "play only topics whose name contains one of these");
  app.add_option("--robots", robots, "play only these robots' messages (the mission clock always plays)");
  app.add_option("--domain", po.domain_id, "DDS domain id")->check(CLI::Range(0, 232));
  app.add_option("--peer", po.initial_peers, "IPv4 address of a DDS peer; repeatable");
  app.add_option("--security", po.security_dir, "DDS Security folder (ca.pem, cert.pem, key.pem)");
  app.add_option("--wait", wait_s, "seconds to wait for subscribers before playing");
  app.add_option("--subscribers", subscribers,
                 "subscribers each played topic must have before playing starts (2: a consumer and a recorder)")
      ->check(CLI::Range(1, 16));
  app.add_option("--log-level", log_level);
  CLI11_PARSE(app, argc, argv);
  cairn::set_log_level(log_level);
  auto log = cairn::make_logger("replay");

  std::ifstream file(path, std::ios::binary);
  if (!file) {
    log->error("{}: cannot be read", path);
    return 2;
  }
  std::string error;
  auto participant = cairn::dds::Participant::create(po, &error);
  if (!participant) {
    log->error("{}", error);
    return 3;
  }
  std::map<uint16_t, ChannelPlay> channels;
  auto channel = [&](uint16_t id, const cairn::bag::McapChannel& c,
                     const std::map<uint16_t, cairn::bag::McapSchema>& schemas) -> ChannelPlay& {
    auto [it, added] = channels.try_emplace(id);
    if (!added) return it->second;
    ChannelPlay& play = it->second;
    play.topic = c.topic;
    play.type_name = schemas.count(c.schema_id) ? schemas.at(c.schema_id).name : "";
    std::string why;
    if (!cairn::bag::topic_wanted(c.topic, topics)) {
      log->debug("{}: not asked for", c.topic);
    } else if (c.message_encoding != "cdr") {
      log->warn("{}: message encoding \"{}\" is not CDR: not played", c.topic, c.message_encoding);
    } else if (!(play.player = cairn::bag::make_player(*participant, c.topic, play.type_name, &why))) {
      log->warn("{}: not played", why);
    }
    return play;
  };
  // Writers for every channel the summary lists, so subscribers can match before the first message.
  if (auto summary = cairn::bag::read_mcap_summary(file, &error)) {
    for (const auto& [id, c] : summary->channels) channel(id, c, summary->schemas);
    log->info("{}: {} messages on {} channels over {:.1f} s", path, summary->message_count, summary->channels.size(),
              1e-9 * double(summary->end_ns - summary->start_ns));
  } else {
    log->warn("{}: {}; reading it from the start", path, error);
  }
  file.clear();
  const auto wait_until = Clock::now() + std::chrono::duration<double>(wait_s);
  while (Clock::now() < wait_until && std::any_of(channels.begin(), channels.end(), [&](const auto& c) {
           return c.second.player && c.second.player->matched_readers() < subscribers;
         })) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }

  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  cairn::bag::McapReader reader(file);
  cairn::bag::McapMessage m;
  size_t problems_logged = 0;
  uint64_t first_ns = 0, last_ns = 0, messages = 0;
  const auto start = Clock::now();
  while (!g_stop && reader.next(&m)) {
    for (; problems_logged < reader.problems().size(); ++problems_logged) {
      log->error("{}: {}", path, reader.problems()[problems_logged]);
    }
    if (messages++ == 0) first_ns = m.log_time_ns;
    last_ns = std::max(last_ns, m.log_time_ns);
    ChannelPlay& play = channel(m.channel_id, reader.channels().at(m.channel_id), reader.schemas());
    if (!play.player) continue;
    if (speed > 0 && m.log_time_ns > first_ns) {
      std::this_thread::sleep_until(start +
                                    std::chrono::nanoseconds(int64_t(double(m.log_time_ns - first_ns) / speed)));
    }
    switch (play.player->play(m.data, robots)) {
      case cairn::bag::PlayResult::kWritten:
        ++play.written;
        break;
      case cairn::bag::PlayResult::kFilteredOut:
        ++play.filtered;
        break;
      case cairn::bag::PlayResult::kWriteFailed:
        ++play.failed;
        break;
      case cairn::bag::PlayResult::kUndecodable:
        if (play.undecodable++ == 0) {
          log->error("{}: message {} on {} (log time {} ns) does not decode as {}: skipped", path, m.sequence,
                     play.topic, m.log_time_ns, play.type_name);
        }
        break;
    }
  }
  for (; problems_logged < reader.problems().size(); ++problems_logged) {
    log->error("{}: {}", path, reader.problems()[problems_logged]);
  }
  uint64_t written = 0, skipped = 0;
  for (auto& [id, play] : channels) {
    written += play.written;
    skipped += play.undecodable + play.failed;
    if (play.undecodable || play.failed) {
      log->warn("{}: {} messages did not decode, {} could not be written", play.topic, play.undecodable, play.failed);
    }
    if (play.player && !play.player->flush(5.0)) log->warn("{}: not every subscriber acknowledged", play.topic);
  }
  const double wall_s = std::chrono::duration<double>(Clock::now() - start).count();
  const double span_s = 1e-9 * double(last_ns - first_ns);
  log->info("replayed {} of {} messages ({:.1f} s of mission in {:.1f} s, {:.1f}x real time){}", written, messages,
            span_s, wall_s, wall_s > 0 ? span_s / wall_s : 0.0,
            reader.finished_cleanly() ? "" : "; the recording was not closed cleanly");
  return reader.problems().empty() && skipped == 0 ? 0 : 5;
}
