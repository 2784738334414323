#pragma once
// ObjectIdRegistry: object ids that stay stable for the whole mission. An object is shown to the
// team under an id the moment it is first computed (in a robot's own frame or on the global map);
// when robots link or reports merge, the merged object keeps the id shown first and lists the
// others as aliases, so "victim 1-3" never silently becomes "victim 0-2". An object whose reports
// no longer merge keeps the old id for one part and gives the other its own smallest report id.
#include <cstdint>
#include <map>
#include <set>
#include <vector>

#include "base_station/core/global_object.h"
#include "common/ids.h"

namespace cairn::base {

class ObjectIdRegistry {
 public:
  /// Sets each object's id and aliases (objects in id order on return).
  void assign(std::vector<GlobalObject>* objects);

 private:
  std::map<ObjectId, ObjectId> shown_as_;     ///< report -> the id its object was shown under
  std::map<ObjectId, uint64_t> first_shown_;  ///< shown id -> when it was first shown (order)
  uint64_t next_ = 0;
};

}  // namespace cairn::base
