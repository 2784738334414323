// The base's journal (base_station/store/journal.h) as a restarted base reads it: any file where
// the journal should be is opened, loaded and every record decoded as BaseNode::restore does. A
// foreign or damaged file must be refused or its bad rows skipped, never crash the base.
#include <cstdio>

#include "fuzz/decode_record.h"
#include "fuzz/fuzz_input.h"

namespace {

using namespace cairn;

// A journal holding one record of each kind, as a base writes them.
void write_seed(const std::string& dir) {
  const std::string path = dir + "/journal.sqlite";
  std::remove(path.c_str());
  std::string error;
  base::JournalOptions options;
  options.sync_full = false;
  auto journal = base::Journal::open(path, options, &error);
  if (!journal) return;
  cairn_msgs::ObjectReport object;
  object.robot_id(1);
  object.class_name("victim");
  base::CommandRecord command;
  command.seq = 1;
  command.robot = RobotId(1);
  base::VerdictRecord verdict;
  verdict.object = {RobotId(1), 0};
  verdict.verdict = base::ObjectVerdict::kConfirmed;
  base::SearchControlRecord search;
  search.seq = 1;
  const auto text = [](const std::string& s) { return std::vector<uint8_t>(s.begin(), s.end()); };
  journal->append({{base::JournalKind::kObject, RobotId(1), 0, dds::to_cdr<cairn_msgs::ObjectReportPubSubType>(object)},
                   {base::JournalKind::kKeyframePoses, RobotId(1), 0,
                    dds::to_cdr<cairn_msgs::KeyframePosesPubSubType>(cairn_msgs::KeyframePoses())},
                   {base::JournalKind::kStatus, RobotId(1), 0,
                    dds::to_cdr<cairn_msgs::RobotStatusPubSubType>(cairn_msgs::RobotStatus())},
                   {base::JournalKind::kCommand, RobotId(1), 1, text(base::command_record_to_json(command))},
                   {base::JournalKind::kVerdict, RobotId(1), 0, text(base::verdict_record_to_json(verdict))},
                   {base::JournalKind::kSearch, RobotId(0), 1, text(base::search_record_to_json(search))}},
                  &error);
  journal.reset();  // closes it; SQLite folds the write-ahead log back into the file
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const std::string dir = fuzz::seeds_dir(); !dir.empty()) write_seed(dir);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = fuzz::write_input(data, size, "journal.sqlite");
  for (const char* suffix : {"-wal", "-shm"}) std::remove((path + suffix).c_str());  // last input's
  std::string error;
  base::JournalOptions options;
  options.sync_full = false;
  options.busy_timeout_ms = 0;
  const auto journal = base::Journal::open(path, options, &error);
  if (!journal) return 0;
  if (const auto contents = journal->load(&error)) {
    for (const base::JournalRecord& r : contents->records) fuzz::decode_journal_payload(r.kind, r.payload);
  }
  return 0;
}
