// The base's linking replayed offline: a mission's journal (every keyframe the base stored, with its
// mission stamp) fed back into a MultiRobotMapper in stamp order, one optimize() per second of
// mission time, as the base does live. Prints when each robot got linked, how, and how far its
// placement is from the truth (its start in the world file): the time to link of the same robots'
// data under other link options, minutes of mission in seconds, and without the robots' behaviour
// changing (the robots drove as they drove in that mission).
//
//   bench_link_replay out/collapsed/map/journal.sqlite worlds/collapsed.yaml --entry-hints 0.5,10
//   [--no-hint-search] [--period 1.0]
//
// Keyframes only (the agents' loop-closed pose updates are left out: the journal keeps only each
// robot's last one, which would give early links the robots' final maps).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "base_station/core/multi_robot_mapper.h"
#include "base_station/store/journal.h"
#include "cairn_msgsPubSubTypes.h"
#include "dds/cdr.h"
#include "dds/conversions.h"
#include "sim/world.h"

namespace {

using namespace cairn;

std::vector<Keyframe> read_keyframes(const std::string& path) {
  std::string error;
  const auto journal = base::Journal::open(path, {}, &error);
  if (!journal) throw std::runtime_error(error);
  const auto contents = journal->load(&error);
  if (!contents) throw std::runtime_error(path + ": " + error);
  std::vector<Keyframe> out;
  for (const base::JournalRecord& r : contents->records) {
    if (r.kind != base::JournalKind::kKeyframe) continue;
    cairn_msgs::Keyframe m;
    if (!dds::from_cdr<cairn_msgs::KeyframePubSubType>(r.payload, &m)) continue;
    if (auto kf = dds::from_msg(m, &error)) out.push_back(std::move(*kf));
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const Keyframe& a, const Keyframe& b) { return a.stamp_ns < b.stamp_ns; });
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Cairn: a mission's linking replayed from its journal"};
  std::string journal_path, world_path, entry_hints;
  double period_s = 1.0;
  bool no_hint_search = false, verbose = false;
  app.add_option("journal", journal_path, "the base's journal.sqlite of the mission")->required();
  app.add_option("world", world_path, "the mission's world file (robot 0's start anchors, the others' are the truth)")
      ->required();
  app.add_option("--entry-hints", entry_hints, "SIGMA_XY_M,SIGMA_YAW_DEG as cairn_mission gives them");
  app.add_option("--period", period_s, "mission seconds between optimize() calls")->check(CLI::PositiveNumber);
  app.add_flag("--verbose", verbose, "every link decision, refusals too");
  app.add_flag("--no-hint-search", no_hint_search, "entry hints gate Scan Context only (MapperOptions)");
  CLI11_PARSE(app, argc, argv);
  try {
    const sim::WorldFile wf = sim::load_world_file(world_path);
    const std::vector<Keyframe> keyframes = read_keyframes(journal_path);
    if (keyframes.empty()) throw std::runtime_error(journal_path + ": no keyframes");
    base::MapperOptions options;
    options.entry_hint_search.enabled = !no_hint_search;
    base::MultiRobotMapper mapper(options);
    mapper.set_robot_start(wf.world.robots.front().id, wf.world.robots.front().T_world_start);
    if (!entry_hints.empty()) {
      const auto sigmas = sim::parse_entry_hint_sigmas(entry_hints);
      if (!sigmas) throw std::runtime_error("--entry-hints '" + entry_hints + "': expected SIGMA_XY_M,SIGMA_YAW_DEG");
      const double sigma_xy_m = sigmas->xy_m, sigma_yaw_rad = sigmas->yaw_deg * M_PI / 180.0;
      for (size_t i = 1; i < wf.world.robots.size(); ++i) {
        mapper.set_entry_hint(wf.world.robots[i].id, {sim::entry_hint_guess(wf.world, i, sigma_xy_m, sigma_yaw_rad),
                                                      sigma_xy_m, sigma_yaw_rad});
      }
    }
    // Each robot's first keyframe against its start in the world file (the robots start at their
    // local origin), relative to the anchor's: a wrong link is metres off, drift decimetres.
    const RobotId anchor = wf.world.robots.front().id;
    const auto first_global = [&](RobotId robot) {
      const auto kf = mapper.keyframes().lower_bound(KeyframeId{robot, 0});
      return *mapper.global_pose(kf->first) * kf->second.T_local_base.inverse();
    };
    const auto start_error = [&](const sim::RobotSpec& spec) {
      const SE2 truth = wf.world.robots.front().T_world_start.between(spec.T_world_start);
      return truth.between(first_global(anchor).between(first_global(spec.id)));
    };
    const StampNs period_ns = StampNs(period_s * 1e9);
    size_t next = 0;
    std::map<RobotId, double> worst_m;  // each robot's start, furthest off the truth at any time
    for (StampNs t = keyframes.front().stamp_ns; next < keyframes.size(); t += period_ns) {
      for (; next < keyframes.size() && keyframes[next].stamp_ns <= t; ++next) mapper.add_keyframe(keyframes[next]);
      const base::OptimizeResult r = mapper.optimize();
      for (const base::LinkEvent& e : r.link_events) {
        if (verbose || (e.accepted && e.reason != "linked")) {
          std::printf("%7.1f s  robot %d <-> %d: %s\n", double(t) * 1e-9, e.robot.value, e.other.value,
                      e.reason.c_str());
          for (const cairn::base::LoopClosure& c : verbose ? e.members : std::vector<cairn::base::LoopClosure>{}) {
            std::printf("           %s - %s  %.2f %.2f %.1f deg\n", to_string(c.a).c_str(), to_string(c.b).c_str(),
                        c.T_a_b.x(), c.T_a_b.y(), c.T_a_b.yaw() * 180.0 / M_PI);
          }
        }
      }
      for (RobotId robot : r.newly_linked) std::printf("%7.1f s  robot %d linked\n", double(t) * 1e-9, robot.value);
      if (mapper.linked(anchor)) {
        if (verbose) std::printf("%7.1f s  starts off:", double(t) * 1e-9);
        for (const sim::RobotSpec& spec : wf.world.robots) {
          if (!mapper.linked(spec.id)) continue;
          const double off_m = start_error(spec).translation().norm();
          worst_m[spec.id] = std::max(worst_m[spec.id], off_m);
          if (verbose) std::printf(" %d %.2f m", spec.id.value, off_m);
        }
        if (verbose) std::printf("\n");
      }
    }
    while (mapper.refinement_pending()) mapper.optimize();
    std::printf(
        "\nrobot  time to link  start off the truth (relative to robot %d's): at the end, the worst at any time\n",
        anchor.value);
    for (const base::RobotSummary& s : mapper.robots()) {
      const auto spec = std::find_if(wf.world.robots.begin(), wf.world.robots.end(),
                                     [&](const sim::RobotSpec& r) { return r.id == s.id; });
      if (!s.linked || spec == wf.world.robots.end() || !mapper.linked(anchor)) {
        std::printf("%5d  not linked\n", s.id.value);
        continue;
      }
      const SE2 E = start_error(*spec);
      std::printf("%5d  %9.1f s  %.2f m, %.1f deg  %.2f m\n", s.id.value, s.time_to_link_s, E.translation().norm(),
                  std::abs(E.yaw()) * 180.0 / M_PI, worst_m[s.id]);
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_link_replay: %s\n", e.what());
    return 2;
  }
}
