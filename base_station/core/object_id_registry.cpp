#include "base_station/core/object_id_registry.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <optional>

namespace cairn::base {

void ObjectIdRegistry::assign(std::vector<GlobalObject>* objects) {
  // The ids each object's reports were shown under, first shown first.
  std::vector<std::vector<ObjectId>> known(objects->size());
  for (size_t i = 0; i < objects->size(); ++i) {
    for (ObjectId report : (*objects)[i].reports) {
      const auto it = shown_as_.find(report);
      if (it != shown_as_.end() && std::find(known[i].begin(), known[i].end(), it->second) == known[i].end())
        known[i].push_back(it->second);
    }
    std::sort(known[i].begin(), known[i].end(),
              [&](ObjectId a, ObjectId b) { return first_shown_.at(a) < first_shown_.at(b); });
  }
  std::set<ObjectId> taken;  // one object per id in this call
  std::vector<std::optional<ObjectId>> id(objects->size());
  auto own = [&](size_t i, ObjectId k) {
    const auto& r = (*objects)[i].reports;
    return std::find(r.begin(), r.end(), k) != r.end();
  };
  // 1. An id goes first to the object that still holds the report it was born from (after a split,
  //    the part with that report keeps it).
  for (size_t i = 0; i < objects->size(); ++i) {
    for (ObjectId k : known[i]) {
      if (own(i, k) && !taken.count(k)) {
        id[i] = k;
        taken.insert(k);
        break;
      }
    }
  }
  // 2. Then the earliest shown id not taken; else its own smallest free report id (a new object, or
  //    the part of a split that lost its id).
  for (size_t i = 0; i < objects->size(); ++i) {
    if (id[i]) continue;
    for (ObjectId k : known[i]) {
      if (!taken.count(k)) {
        id[i] = k;
        break;
      }
    }
    for (size_t r = 0; !id[i] && r < (*objects)[i].reports.size(); ++r) {
      if (!taken.count((*objects)[i].reports[r])) id[i] = (*objects)[i].reports[r];
    }
    if (!id[i]) id[i] = (*objects)[i].id;  // every report id taken: cannot happen with disjoint reports
    taken.insert(*id[i]);
  }
  // 3. Aliases: every id ever shown that no object holds now stays findable, as an alias of one
  //    object: the one holding the report the id was born from, else one whose reports were shown
  //    under it. (The ids the reports are shown under now are not enough: after one refresh a merged
  //    object's reports all carry its id, and the alias it had for a second was gone.)
  std::set<ObjectId> current;
  for (size_t i = 0; i < objects->size(); ++i) current.insert(*id[i]);
  std::map<ObjectId, size_t> alias_owner;
  for (size_t i = 0; i < objects->size(); ++i) {
    for (ObjectId report : (*objects)[i].reports) {
      const auto h = history_.find(report);
      if (h == history_.end()) continue;
      for (ObjectId k : h->second) {
        if (current.count(k)) continue;
        if (own(i, k) || !alias_owner.count(k)) alias_owner[k] = i;
      }
    }
  }
  for (GlobalObject& o : *objects) o.aliases.clear();
  for (const auto& [k, i] : alias_owner) (*objects)[i].aliases.push_back(k);  // in id order
  for (size_t i = 0; i < objects->size(); ++i) {
    GlobalObject& o = (*objects)[i];
    o.id = *id[i];
    if (!first_shown_.count(o.id)) first_shown_[o.id] = next_++;
    for (ObjectId report : o.reports) {
      note_history(report, o.id);
      auto [it, added] = shown_as_.emplace(report, o.id);
      if (!added && it->second == o.id) continue;
      it->second = o.id;
      new_entries_.push_back({report, o.id, first_shown_.at(o.id)});
    }
  }
  std::sort(objects->begin(), objects->end(), [](const GlobalObject& a, const GlobalObject& b) { return a.id < b.id; });
}

void ObjectIdRegistry::note_history(ObjectId report, ObjectId shown) {
  std::vector<ObjectId>& h = history_[report];
  if (std::find(h.begin(), h.end(), shown) == h.end()) h.push_back(shown);
}

std::vector<ObjectIdRegistry::Entry> ObjectIdRegistry::take_new_entries() {
  std::vector<Entry> out;
  out.swap(new_entries_);
  return out;
}

bool ObjectIdRegistry::restore(const Entry& e) {
  const auto it = first_shown_.find(e.shown);
  if (it != first_shown_.end() && it->second != e.order) return false;
  for (const auto& [id, order] : first_shown_) {
    if (order == e.order && id != e.shown) return false;
  }
  first_shown_[e.shown] = e.order;
  shown_as_[e.report] = e.shown;
  note_history(e.report, e.shown);
  next_ = std::max(next_, e.order + 1);
  return true;
}

std::vector<uint8_t> object_id_record_to_json(const ObjectIdRegistry::Entry& e) {
  const nlohmann::json j = {{"report", {e.report.robot.value, e.report.seq}},
                            {"shown", {e.shown.robot.value, e.shown.seq}},
                            {"order", e.order}};
  const std::string text = j.dump();
  return {text.begin(), text.end()};
}

std::optional<ObjectIdRegistry::Entry> object_id_record_from_json(const std::vector<uint8_t>& payload,
                                                                  std::string* error) {
  const nlohmann::json j = nlohmann::json::parse(payload.begin(), payload.end(), nullptr, false);
  auto id = [&](const char* key) -> std::optional<ObjectId> {
    if (!j.is_object() || !j.contains(key) || !j[key].is_array() || j[key].size() != 2 ||
        !j[key][0].is_number_integer() || !j[key][1].is_number_integer() || j[key][0].get<int64_t>() < 0 ||
        j[key][1].get<int64_t>() < 0) {
      *error = std::string("object id record: '") + key + "' is not [robot, seq] of two non-negative integers";
      return std::nullopt;
    }
    return ObjectId{RobotId(j[key][0].get<int32_t>()), j[key][1].get<int32_t>()};
  };
  const auto report = id("report"), shown = report ? id("shown") : std::nullopt;
  if (!shown) return std::nullopt;
  if (!j.contains("order") || !j["order"].is_number_unsigned()) {
    *error = "object id record: 'order' is not a non-negative integer";
    return std::nullopt;
  }
  return ObjectIdRegistry::Entry{*report, *shown, j["order"].get<uint64_t>()};
}

}  // namespace cairn::base
