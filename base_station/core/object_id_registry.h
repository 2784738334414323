#pragma once
// ObjectIdRegistry: object ids that stay stable for the whole mission. An object is shown to the
// team under an id the moment it is first computed (in a robot's own frame or on the global map);
// when robots link or reports merge, the merged object keeps the id shown first and lists the
// others as aliases, so "victim 1-3" never silently becomes "victim 0-2". An object whose reports
// no longer merge keeps the old id for one part and gives the other its own smallest report id.
// Every id ever shown that no object holds stays an alias of one object for the whole mission (and
// after a restart: the journaled entries carry the history).
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "base_station/core/global_object.h"
#include "common/ids.h"

namespace cairn::base {

class ObjectIdRegistry {
 public:
  /// One fact the registry learnt: `report` was shown under `shown`, an id first shown as the
  /// `order`-th. A base that restarts restores these (journaled) before it computes any object,
  /// so that it shows every victim under the id the team already knows.
  struct Entry {
    ObjectId report;
    ObjectId shown;
    uint64_t order = 0;
  };

  /// Sets each object's id and aliases (objects in id order on return).
  void assign(std::vector<GlobalObject>* objects);
  /// Entries learnt since the last call (to journal), oldest first.
  std::vector<Entry> take_new_entries();
  /// Takes an entry learnt before a restart. False when it contradicts the order restored so far
  /// (an id first shown at two places in the order).
  bool restore(const Entry& e);

 private:
  std::vector<Entry> new_entries_;
  std::map<ObjectId, ObjectId> shown_as_;              ///< report -> the id its object was shown under
  std::map<ObjectId, uint64_t> first_shown_;           ///< shown id -> when it was first shown (order)
  std::map<ObjectId, std::vector<ObjectId>> history_;  ///< report -> every id it was shown under
  void note_history(ObjectId report, ObjectId shown);
  uint64_t next_ = 0;
};

/// The journal's record of an entry (JSON {"report": [robot, seq], "shown": [robot, seq], "order": n}),
/// and back; nullopt with `error` naming what is wrong.
std::vector<uint8_t> object_id_record_to_json(const ObjectIdRegistry::Entry& e);
std::optional<ObjectIdRegistry::Entry> object_id_record_from_json(const std::vector<uint8_t>& payload,
                                                                  std::string* error);

}  // namespace cairn::base
