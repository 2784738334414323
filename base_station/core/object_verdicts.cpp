#include "base_station/core/object_verdicts.h"

namespace cairn::base {

void ObjectVerdicts::set(const VerdictRecord& record) { records_[record.object] = record; }

void ObjectVerdicts::apply(std::vector<GlobalObject>* objects) const {
  for (GlobalObject& o : *objects) {
    const VerdictRecord* newest = nullptr;
    const auto consider = [&](ObjectId id) {
      const auto it = records_.find(id);
      if (it != records_.end() && (!newest || it->second.at_ns >= newest->at_ns)) newest = &it->second;
    };
    consider(o.id);
    for (ObjectId id : o.aliases) consider(id);
    for (ObjectId id : o.reports) consider(id);
    o.verdict = newest ? newest->verdict : ObjectVerdict::kUnreviewed;
    o.verdict_note = newest ? newest->note : "";
  }
}

}  // namespace cairn::base
