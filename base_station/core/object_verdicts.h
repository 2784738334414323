#pragma once
// The operator's verdicts on objects (confirmed, false, a note), kept apart from the merged objects
// they judge: a verdict is given under the id the console showed, and objects keep merging after
// it (ObjectIdRegistry gives a merged object the first id shown and lists the others as aliases).
// apply() gives each merged object the newest verdict given under any of its ids. Pure.
#include <map>
#include <string>
#include <vector>

#include "base_station/core/global_object.h"
#include "common/ids.h"
#include "common/time.h"

namespace cairn::base {

struct VerdictRecord {
  ObjectId object;  ///< the id it was given under
  ObjectVerdict verdict = ObjectVerdict::kUnreviewed;
  std::string note;
  StampNs at_ns = 0;  ///< mission time: the newest of several verdicts on one merged object wins
};

class ObjectVerdicts {
 public:
  /// Records (or replaces) the verdict given under `record.object`.
  void set(const VerdictRecord& record);
  /// Every object in `objects` gets the newest verdict given under its id, an alias or a report.
  void apply(std::vector<GlobalObject>* objects) const;
  const std::map<ObjectId, VerdictRecord>& records() const { return records_; }

 private:
  std::map<ObjectId, VerdictRecord> records_;
};

}  // namespace cairn::base
