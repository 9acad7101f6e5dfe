#pragma once
// Reading changes.json (docs/objects.md, "Outputs"): which entries still stand. An object
// removed ("removed", or "moved": removed from its old place) and later found again at its
// place has a "restored" entry after its removal: it is live again, and readers that
// collect removed objects (metrics, viewers, move linking) must not count it as gone.

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace ocg {

// Whether each of count entries is a removal not undone by a later "restored" entry of the
// same object; type_and_id(i) gives entry i's type and object id (a pair).
template <typename TypeAndId>
std::vector<bool> StandingRemovalsBy(std::size_t count, const TypeAndId& type_and_id) {
  std::vector<bool> standing(count, false);
  std::map<std::int64_t, std::size_t> last_removal;  // object id -> entry index
  for (std::size_t i = 0; i < count; ++i) {
    const auto [type, id] = type_and_id(i);
    if (type == "removed" || type == "moved") {
      standing[i] = true;
      last_removal[id] = i;
    } else if (type == "restored") {
      const auto removal = last_removal.find(id);
      if (removal != last_removal.end()) standing[removal->second] = false;
    }
  }
  return standing;
}

// StandingRemovalsBy over changes (the JSON list under "changes", taken as a template so
// that this header needs no JSON library). Entries without "type" or "object_id" throw as
// Json::at does.
template <typename Json>
std::vector<bool> StandingRemovals(const Json& changes) {
  return StandingRemovalsBy(changes.size(), [&changes](std::size_t i) {
    const auto& entry = changes[i];
    return std::make_pair(entry.at("type").template get<std::string>(),
                          entry.at("object_id").template get<std::int64_t>());
  });
}

}  // namespace ocg
