#pragma once
// What a session's change log pairs removals and appearances by (change_log.h): when the
// session saw each object as its class, and how the objects a between-session pairing
// weighs look (their boxes' descriptors, their colours). Over the object map's live
// objects and the objects removed in this run.

#include <cstdint>
#include <map>
#include <opencv2/core/mat.hpp>
#include <vector>

#include "ocg/objects/box_appearance.h"
#include "ocg/objects/colour_signature.h"
#include "ocg/objects/map_diff.h"
#include "ocg/objects/map_object.h"

namespace ocg {

// The objects of one session's pairing: the live ones and those removed in this run (as
// they were when removed), session and the frame it started at.
struct SessionObjects {
  const std::map<ObjectId, MapObject>& live;
  const std::map<ObjectId, MapObject>& removed_in_run;
  int session = 0;
  std::int64_t session_first_frame = 0;
};

// ObjectMap::SeenAsClassThisSession.
SeenAsClass SeenAsClassIn(const SessionObjects& objects);
// ObjectMap::BoxAppearances.
std::map<ObjectId, std::vector<Descriptor>> BoxAppearancesOf(const SessionObjects& objects,
                                                             const KeyframeFeatureMap& keyframes,
                                                             const BoxAppearanceOptions& options,
                                                             int max_distance,
                                                             const ObjectMapContext& context);
// ObjectMap::ColourAppearances.
std::map<ObjectId, ColourHistogram> ColourAppearancesOf(const SessionObjects& objects,
                                                        int min_signatures);
// The colour signature (BoxColourSignature of bgr, the image of frame) of every sighting of
// object made at frame; returns how many were given one.
int SetSightingColoursOf(MapObject& object, std::int64_t frame, const cv::Mat& bgr,
                         const ColourSignatureOptions& options);

}  // namespace ocg
