#pragma once
// Reading changes.json (docs/objects.md, "Outputs"): which entries still stand. An object
// removed ("removed", or "moved": removed from its old place) and later found again at its
// place has a "restored" entry after its removal: it is live again, and readers that
// collect removed objects (metrics, viewers, move linking) must not count it as gone.

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace ocg {

// Whether each entry of changes (the JSON list under "changes", taken as a template so
// that this header needs no JSON library) is a removal not undone by a later "restored"
// entry of the same object_id. Entries without "type" or "object_id" throw as Json::at does.
template <typename Json>
std::vector<bool> StandingRemovals(const Json& changes) {
  std::vector<bool> standing(changes.size(), false);
  std::map<std::int64_t, std::size_t> last_removal;  // object id -> entry index
  for (std::size_t i = 0; i < changes.size(); ++i) {
    const auto& entry = changes[i];
    const auto type = entry.at("type").template get<std::string>();
    const auto id = entry.at("object_id").template get<std::int64_t>();
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

}  // namespace ocg
