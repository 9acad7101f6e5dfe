#pragma once
// The 3-D map snapshot: map points, keyframe frustums, the trajectory (and the ground
// truth's), and the object cuboids coloured by OCG state, removed objects as grey dashed
// ghosts, moves as arrows from the old place to the new, with class labels. Rendered off-screen
// (OSMesa) into an image.
//
// Threading: RenderMapView uses the caller's Renderer (one thread per Renderer).

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "ocg/core/lie.h"
#include "ocg/objects/object_map.h"
#include "ocg/render/renderer.h"
#include "ocg/viewer/label_layout.h"
#include "ocg/viewer/viewer_options.h"

namespace ocg {

// What a map snapshot shows, in the map's world frame.
struct MapScene {
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();  // gravity-aligned cuboids' up
  std::vector<Eigen::Vector3d> points;
  std::vector<SE3> keyframes;                // camera-to-world (T_wc)
  std::vector<Eigen::Vector3d> trajectory;   // camera centres, in order
  std::vector<Eigen::Vector3d> groundtruth;  // aligned to the map, in order; may be empty
  std::vector<ObjectView> objects;
  // Moved objects: old centre to new centre, drawn as magenta arrows.
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> moves;
  std::optional<SE3> current_camera;  // T_wc of the last tracked frame, drawn in green
  // The trajectory's name in the legend (pose-given runs: "given camera path").
  std::string trajectory_name = "camera path";
  // Words added to each object's label (objects' order: ocg_diff's "added", "moved here");
  // shorter than objects or empty: none for the rest.
  std::vector<std::string> notes;
};

enum class MapViewpoint {
  kFollow,        // ORB-SLAM2's view: Viewer.ViewpointX/Y/Z/F behind the last keyframe
  kTopDown,       // from above, framing the whole map
  kThreeQuarter,  // from 45 degrees round and 35 up, framing the whole map
  kObjects,       // as kThreeQuarter, framing the objects (the whole map without any)
};
const char* ToString(MapViewpoint viewpoint);

// The colour of an OCG state (RGB in [0, 1]); state 5 / removed: grey.
Eigen::Vector3f StateColour(int state, bool removed);

// Where the snapshot camera is and how it projects, for a viewpoint of the scene.
struct ViewCamera {
  SE3 T_cw;
  PinholeCamera camera;
};
ViewCamera MapViewCamera(const MapScene& scene, const ViewerOptions& options,
                         MapViewpoint viewpoint);

// What the legend of a snapshot of scene lists: only what is drawn. The OCG states of its
// live objects ("observed", "recently observed", "unknown", "suspicious", "not judged
// yet"), "removed" for ghosts, "moved" for arrows, then the keyframes, the trajectory
// (scene.trajectory_name) and the "ground truth" when there are any. Empty for an empty
// scene (no legend is drawn).
std::vector<std::string> MapLegend(const MapScene& scene);

// The objects' labels ("id class", and its note) as RenderMapView draws them: live
// objects first, nearest first, then ghosts; none overlapping another or the legend, a
// label moved from its place drawn with a leader line; a label with no free place near
// its object is left out.
std::vector<PlacedLabel> MapViewLabels(const MapScene& scene, const ViewerOptions& options,
                                       MapViewpoint viewpoint);

// The snapshot (BGR, options.snapshot_width x snapshot_height). An empty scene renders
// as the background.
cv::Mat RenderMapView(Renderer& renderer, const MapScene& scene, const ViewerOptions& options,
                      MapViewpoint viewpoint);

}  // namespace ocg
