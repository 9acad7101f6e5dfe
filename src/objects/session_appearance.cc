#include "ocg/objects/session_appearance.h"

#include <optional>

namespace ocg {
namespace {

// visit(object, removed) for each object a between-session pairing weighs (a later session
// only): each one removed in this run and last seen in an earlier session (removed true)
// and each live one seen in this session alone (removed false).
template <typename Visit>
void ForEachBetweenSessionCandidate(const SessionObjects& objects, Visit&& visit) {
  if (objects.session == 0) return;
  for (const auto& [id, object] : objects.removed_in_run) {
    if (!object.sightings.empty() && object.sightings.back().session < objects.session)
      visit(object, true);
  }
  for (const auto& [id, object] : objects.live) {
    if (!object.sightings.empty() && object.sightings.front().session == objects.session)
      visit(object, false);
  }
}

// visit(object) for each live object and each one removed in this run.
template <typename Visit>
void ForEachObject(const SessionObjects& objects, Visit&& visit) {
  for (const auto& [id, object] : objects.live) visit(object);
  for (const auto& [id, object] : objects.removed_in_run) visit(object);
}

}  // namespace

SeenAsClass SeenAsClassIn(const SessionObjects& objects) {
  SeenAsClass seen;
  const auto add = [&](const MapObject& object) {
    bool earlier = false;
    const SightingHistory::ClassSpan* now = nullptr;
    for (const auto& [key, span] : object.sightings.spans()) {
      if (key.second != object.class_id) continue;
      if (key.first != objects.session) {
        earlier = true;
      } else {
        now = &span;
      }
    }
    if (now == nullptr) return;
    if (!earlier) seen.first[object.id] = now->SupportedFirst();
    seen.last[object.id] = now->SupportedLast();
  };
  ForEachObject(objects, add);
  return seen;
}

std::map<ObjectId, std::vector<Descriptor>> BoxAppearancesOf(const SessionObjects& objects,
                                                             const KeyframeFeatureMap& keyframes,
                                                             const BoxAppearanceOptions& options,
                                                             int max_distance,
                                                             const ObjectMapContext& context) {
  options.Check();
  std::vector<const KeyframeFeatures*> earlier, now;
  for (const auto& [frame, keyframe] : keyframes)
    (frame < objects.session_first_frame ? earlier : now).push_back(&keyframe);
  std::map<ObjectId, std::vector<Descriptor>> appearances;
  const auto add = [&](const MapObject& object,
                       const std::vector<const KeyframeFeatures*>& absent) {
    if (!object.has_cuboid) return;
    std::vector<FrameBox> boxes;
    for (const ObjectSighting& sighting : object.sightings)
      boxes.push_back({sighting.frame, sighting.box});
    std::vector<Descriptor> descriptors = WithoutBackground(
        BoxDescriptors(boxes, object.cuboid, context.R_wg, keyframes, options),
        options.place_background
            ? PlaceDescriptors(object.cuboid, context.R_wg, context.camera, absent, options)
            : std::vector<Descriptor>{},
        max_distance);
    if (!descriptors.empty()) appearances[object.id] = std::move(descriptors);
  };
  ForEachBetweenSessionCandidate(objects, [&](const MapObject& object, bool removed) {
    add(object, removed ? now : earlier);
  });
  return appearances;
}

std::map<ObjectId, ColourHistogram> ColourAppearancesOf(const SessionObjects& objects,
                                                        int min_signatures) {
  std::map<ObjectId, ColourHistogram> colours;
  const auto add = [&](const MapObject& object) {
    std::vector<ColourHistogram> signatures;
    for (const ObjectSighting& sighting : object.sightings) {
      if (sighting.colour) signatures.push_back(*sighting.colour);
    }
    if (static_cast<int>(signatures.size()) < min_signatures) return;
    if (std::optional<ColourHistogram> mean = MeanColour(signatures)) colours[object.id] = *mean;
  };
  ForEachObject(objects, add);
  return colours;
}

int SetSightingColoursOf(MapObject& object, std::int64_t frame, const cv::Mat& bgr,
                         const ColourSignatureOptions& options) {
  int set = 0;
  for (ObjectSighting& sighting : object.sightings) {
    if (sighting.frame != frame) continue;
    sighting.colour = BoxColourSignature(bgr, sighting.box, options);
    if (sighting.colour) ++set;
  }
  return set;
}

}  // namespace ocg
