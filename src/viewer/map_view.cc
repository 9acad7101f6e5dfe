#include "ocg/viewer/map_view.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "drawing.h"
#include "ocg/core/coco.h"
#include "ocg/core/statistics.h"

namespace ocg {
namespace {

constexpr double kPi = 3.14159265358979323846;

Eigen::Vector3f ToFloat(const Eigen::Vector3d& v) { return v.cast<float>(); }

// The scene's extent in the gravity frame: the points' 2-98 % range (a few far outliers
// must not shrink the map to a dot) joined with everything else.
void SceneBounds(const MapScene& scene, const Eigen::Matrix3d& R_wg, bool trim_points,
                 Eigen::Vector3d* low, Eigen::Vector3d* high) {
  *low = Eigen::Vector3d::Constant(1e300);
  *high = -*low;
  const auto include = [&](const Eigen::Vector3d& p_w) {
    const Eigen::Vector3d p = R_wg.transpose() * p_w;
    *low = low->cwiseMin(p);
    *high = high->cwiseMax(p);
  };
  if (trim_points && scene.points.size() >= 50) {
    for (int axis = 0; axis < 3; ++axis) {
      std::vector<double> values;
      values.reserve(scene.points.size());
      for (const Eigen::Vector3d& p : scene.points) values.push_back((R_wg.transpose() * p)[axis]);
      (*low)[axis] = std::min((*low)[axis], Quantile(values, 0.02));
      (*high)[axis] = std::max((*high)[axis], Quantile(values, 0.98));
    }
  } else {
    for (const Eigen::Vector3d& p : scene.points) include(p);
  }
  for (const Eigen::Vector3d& p : scene.trajectory) include(p);
  for (const SE3& T_wc : scene.keyframes) include(T_wc.translation());
  for (const ObjectView& object : scene.objects) include(object.cuboid.centre);
  for (const auto& [from, to] : scene.moves) {
    include(from);
    include(to);
  }
  if ((*low)[0] > (*high)[0]) {  // nothing at all
    *low = Eigen::Vector3d::Constant(-1.0);
    *high = Eigen::Vector3d::Constant(1.0);
  }
  // A flat or single-point scene still needs a size to frame.
  const Eigen::Vector3d middle = 0.5 * (*low + *high);
  const double least = std::max(0.2, 0.1 * (*high - *low).maxCoeff());
  *low = low->cwiseMin(middle - Eigen::Vector3d::Constant(0.5 * least));
  *high = high->cwiseMax(middle + Eigen::Vector3d::Constant(0.5 * least));
}

void AddSegment(LineBatch& batch, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  batch.segments.push_back(ToFloat(a));
  batch.segments.push_back(ToFloat(b));
}

void AddCuboidEdges(LineBatch& batch, const Cuboid& cuboid, const Eigen::Matrix3d& R_wg) {
  for (const auto& [a, b] : CuboidEdges(cuboid, R_wg)) AddSegment(batch, a, b);
}

// A shaft and a two-stroke head in the horizontal plane, the head a fifth of the length
// within [head, 3 x head], so short moves still read as arrows and long ones stay clean.
void AddArrow(LineBatch& batch, const Eigen::Vector3d& from, const Eigen::Vector3d& to,
              const Eigen::Vector3d& up, double head_min) {
  AddSegment(batch, from, to);
  const Eigen::Vector3d along = to - from;
  if (along.norm() < 1e-9) return;
  const Eigen::Vector3d back = -along.normalized();
  Eigen::Vector3d side = up.cross(back);
  if (side.norm() < 1e-9) side = back.unitOrthogonal();
  side.normalize();
  const double head = std::clamp(0.2 * along.norm(), head_min, 3 * head_min);
  AddSegment(batch, to, to + head * (back + 0.5 * side));
  AddSegment(batch, to, to + head * (back - 0.5 * side));
}

void AddFrustum(LineBatch& batch, const SE3& T_wc, double size) {
  const double w = size, h = 0.75 * size, z = 0.6 * size;
  const Eigen::Vector3d centre = T_wc.translation();
  const std::array<Eigen::Vector3d, 4> corners = {
      T_wc * Eigen::Vector3d(w, h, z), T_wc * Eigen::Vector3d(w, -h, z),
      T_wc * Eigen::Vector3d(-w, -h, z), T_wc * Eigen::Vector3d(-w, h, z)};
  for (int i = 0; i < 4; ++i) {
    AddSegment(batch, centre, corners[i]);
    AddSegment(batch, corners[i], corners[(i + 1) % 4]);
  }
}

const Eigen::Vector3f kArrowColour(0.85f, 0.1f, 0.75f);
const Eigen::Vector3f kKeyframeColour(0.0f, 0.0f, 1.0f);
const Eigen::Vector3f kTrajectoryColour(0.0f, 0.6f, 0.0f);
const Eigen::Vector3f kGroundTruthColour(0.45f, 0.45f, 0.45f);

std::vector<LegendEntry> LegendOf(const MapScene& scene) {
  std::vector<LegendEntry> entries;
  bool drawn[5] = {};
  for (const ObjectView& object : scene.objects) {
    if (!object.removed && object.state >= 0 && object.state < 5) drawn[object.state] = true;
  }
  AddStateEntries(entries, drawn, LegendEntry::Mark::kFilled,
                  [](int state) { return StateColour(state, false); });
  if (std::any_of(scene.objects.begin(), scene.objects.end(),
                  [](const ObjectView& object) { return object.removed; }))
    entries.push_back({LegendEntry::Mark::kDashed, ToBgr(StateColour(5, true)), "removed"});
  if (!scene.moves.empty())
    entries.push_back({LegendEntry::Mark::kArrow, ToBgr(kArrowColour), "moved"});
  if (!scene.keyframes.empty())
    entries.push_back({LegendEntry::Mark::kOutline, ToBgr(kKeyframeColour), "keyframes"});
  if (scene.trajectory.size() >= 2)
    entries.push_back({LegendEntry::Mark::kLine, ToBgr(kTrajectoryColour), scene.trajectory_name});
  if (scene.groundtruth.size() >= 2)
    entries.push_back({LegendEntry::Mark::kLine, ToBgr(kGroundTruthColour), "ground truth"});
  return entries;
}

std::vector<PlacedLabel> LabelsIn(const MapScene& scene, const ViewCamera& view,
                                  const cv::Rect& legend) {
  const Eigen::Matrix3d R_wg = GravityFrame(scene.up);
  struct Candidate {
    bool removed;
    double depth;
    std::size_t index;
    cv::Point anchor;
  };
  std::vector<Candidate> candidates;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const ObjectView& object = scene.objects[i];
    const Eigen::Vector3d top = object.cuboid.centre + 0.5 * object.cuboid.size.z() * R_wg.col(2);
    const Eigen::Vector3d p_c = view.T_cw * top;
    if (p_c.z() <= Renderer::kNear) continue;
    const Eigen::Vector2d pixel = view.camera.ProjectUndistorted(p_c);
    if (pixel.x() < 0 || pixel.y() < 0 || pixel.x() >= view.camera.width ||
        pixel.y() >= view.camera.height)
      continue;
    candidates.push_back({object.removed, p_c.z(), i,
                          cv::Point(static_cast<int>(pixel.x()), static_cast<int>(pixel.y()))});
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& a, const Candidate& b) {
                     if (a.removed != b.removed) return !a.removed;
                     return a.depth < b.depth;
                   });
  std::vector<std::pair<std::string, cv::Point>> labels;
  for (const Candidate& candidate : candidates) {
    const ObjectView& object = scene.objects[candidate.index];
    std::string text = std::to_string(object.id) + " " + CocoClassName(object.class_id);
    if (candidate.index < scene.notes.size() && !scene.notes[candidate.index].empty())
      text += " (" + scene.notes[candidate.index] + ")";
    labels.emplace_back(std::move(text), candidate.anchor);
  }
  std::vector<cv::Rect> obstacles;
  if (legend.area() > 0) obstacles.push_back(legend);
  return LayOutLabels(labels, cv::Size(view.camera.width, view.camera.height), obstacles);
}

}  // namespace

const char* ToString(MapViewpoint viewpoint) {
  switch (viewpoint) {
    case MapViewpoint::kFollow:
      return "follow";
    case MapViewpoint::kTopDown:
      return "top";
    case MapViewpoint::kThreeQuarter:
      return "three_quarter";
    case MapViewpoint::kObjects:
      return "objects";
  }
  return "?";
}

Eigen::Vector3f StateColour(int state, bool removed) {
  if (removed || state == 5) return {0.55f, 0.55f, 0.55f};
  switch (state) {
    case 1:
      return {0.1f, 0.7f, 0.2f};  // observed: green
    case 2:
      return {0.2f, 0.45f, 0.95f};  // recently observed: blue
    case 3:
      return {0.95f, 0.75f, 0.1f};  // unknown: yellow
    case 4:
      return {0.9f, 0.2f, 0.1f};  // suspicious: red
    default:
      return {0.85f, 0.85f, 0.85f};  // not yet judged
  }
}

ViewCamera MapViewCamera(const MapScene& scene, const ViewerOptions& options,
                         MapViewpoint viewpoint) {
  ViewCamera view;
  view.camera.width = options.snapshot_width;
  view.camera.height = options.snapshot_height;
  view.camera.cx = 0.5 * (options.snapshot_width - 1);
  view.camera.cy = 0.5 * (options.snapshot_height - 1);
  view.camera.fx = view.camera.fy = options.snapshot_width;  // 53 degrees across
  const Eigen::Matrix3d R_wg = GravityFrame(scene.up);
  if (viewpoint == MapViewpoint::kFollow && !scene.keyframes.empty()) {
    // ORB-SLAM2's viewer: eye at the viewpoint in the camera's frame, looking at the
    // camera, image up along the camera's up; ViewpointF for a 1024-pixel-wide window.
    const SE3& T_wc = scene.keyframes.back();
    view.camera.fx = view.camera.fy = options.viewpoint_f * options.snapshot_width / 1024.0;
    const Eigen::Vector3d eye =
        T_wc * Eigen::Vector3d(options.viewpoint_x, options.viewpoint_y, options.viewpoint_z);
    view.T_cw = LookAt(eye, T_wc.translation(), T_wc.rotation() * -Eigen::Vector3d::UnitY());
    return view;
  }
  Eigen::Vector3d low, high;
  if (viewpoint == MapViewpoint::kObjects && !scene.objects.empty()) {
    MapScene objects_only;
    for (const ObjectView& object : scene.objects) {
      for (const Eigen::Vector3d& corner : CuboidCorners(object.cuboid, R_wg))
        objects_only.points.push_back(corner);
    }
    SceneBounds(objects_only, R_wg, false, &low, &high);
  } else {
    SceneBounds(scene, R_wg, true, &low, &high);
  }
  const Eigen::Vector3d extent = high - low;
  const Eigen::Vector3d centre = R_wg * (0.5 * (low + high));
  const double f = view.camera.fx;
  if (viewpoint == MapViewpoint::kTopDown) {
    const double distance = std::max(extent.x() * f / (0.9 * options.snapshot_width),
                                     extent.y() * f / (0.9 * options.snapshot_height)) +
                            0.5 * extent.z();
    view.T_cw = LookAt(centre + distance * R_wg.col(2), centre, R_wg.col(1));
    return view;
  }
  const double azimuth = kPi / 4, elevation = 35 * kPi / 180;
  const Eigen::Vector3d direction =
      std::cos(elevation) * (std::cos(azimuth) * R_wg.col(0) + std::sin(azimuth) * R_wg.col(1)) +
      std::sin(elevation) * R_wg.col(2);
  const double radius = 0.5 * extent.norm();
  const double distance =
      radius * f / (0.5 * std::min(options.snapshot_width, options.snapshot_height)) + radius;
  view.T_cw = LookAt(centre + distance * direction, centre, R_wg.col(2));
  return view;
}

cv::Mat RenderMapView(Renderer& renderer, const MapScene& scene, const ViewerOptions& options,
                      MapViewpoint viewpoint) {
  const ViewCamera view = MapViewCamera(scene, options, viewpoint);
  const Eigen::Matrix3d R_wg = GravityFrame(scene.up);
  Eigen::Vector3d low, high;
  SceneBounds(scene, R_wg, true, &low, &high);
  const double frustum_size = std::max(options.keyframe_size, 0.015 * (high - low).maxCoeff());

  Overlay overlay;
  PointBatch points;
  points.colour = Eigen::Vector3f::Zero();
  points.size = static_cast<float>(options.point_size);
  for (const Eigen::Vector3d& p : scene.points) points.positions.push_back(ToFloat(p));
  overlay.points.push_back(std::move(points));

  LineBatch keyframes;
  keyframes.colour = kKeyframeColour;
  keyframes.width = static_cast<float>(options.keyframe_line_width);
  for (const SE3& T_wc : scene.keyframes) AddFrustum(keyframes, T_wc, frustum_size);
  overlay.lines.push_back(std::move(keyframes));
  if (scene.current_camera) {
    LineBatch camera;
    camera.colour = Eigen::Vector3f(0.0f, 0.8f, 0.0f);
    camera.width = static_cast<float>(options.camera_line_width);
    AddFrustum(camera, *scene.current_camera, std::max(options.camera_size, 1.6 * frustum_size));
    overlay.lines.push_back(std::move(camera));
  }
  for (const auto* path : {&scene.groundtruth, &scene.trajectory}) {
    LineBatch line;
    line.colour = path == &scene.trajectory ? kTrajectoryColour : kGroundTruthColour;
    line.width = static_cast<float>(options.graph_line_width) + 1.0f;
    for (std::size_t i = 1; i < path->size(); ++i) AddSegment(line, (*path)[i - 1], (*path)[i]);
    overlay.lines.push_back(std::move(line));
  }

  if (!scene.moves.empty()) {
    LineBatch arrows;
    arrows.colour = kArrowColour;
    arrows.width = 3.0f;
    for (const auto& [from, to] : scene.moves)
      AddArrow(arrows, from, to, R_wg.col(2), 0.015 * (high - low).maxCoeff());
    overlay.lines.push_back(std::move(arrows));
  }

  std::vector<DrawItem> faces;
  faces.reserve(scene.objects.size());
  for (const ObjectView& object : scene.objects) {
    const Eigen::Vector3f colour = StateColour(object.state, object.removed);
    LineBatch edges;
    edges.colour = object.removed ? colour : 0.6f * colour;
    edges.width = 2.0f;
    edges.dashed = object.removed;
    AddCuboidEdges(edges, object.cuboid, R_wg);
    overlay.lines.push_back(std::move(edges));
    if (object.removed) continue;  // a ghost: edges only
    DrawItem item;
    const Eigen::Matrix3d rotation =
        R_wg * Eigen::AngleAxisd(object.cuboid.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    item.mesh = Mesh::Box(object.cuboid.size.cast<float>().cwiseMax(1e-3f))
                    .Transformed(SE3(rotation, object.cuboid.centre));
    item.colour = colour;
    item.shade.clear();
    for (const MeshVertex& vertex : item.mesh.vertices) {
      // Faces lit from above, so the cuboid reads as a solid.
      const float light =
          0.65f + 0.35f * std::max(0.0f, vertex.normal.dot(R_wg.col(2).cast<float>()));
      item.shade.push_back(light * colour);
    }
    faces.push_back(std::move(item));
  }
  std::vector<const DrawItem*> items;
  for (const DrawItem& item : faces) items.push_back(&item);

  cv::Mat image = renderer.RenderColour(items, overlay, view.T_cw, view.camera,
                                        Eigen::Vector3f(1.0f, 1.0f, 1.0f));
  const std::vector<LegendEntry> legend = LegendOf(scene);
  DrawLabels(image, LabelsIn(scene, view, LegendBox(legend)));
  DrawLegend(image, legend);
  return image;
}

std::vector<std::string> MapLegend(const MapScene& scene) {
  std::vector<std::string> texts;
  for (const LegendEntry& entry : LegendOf(scene)) texts.push_back(entry.text);
  return texts;
}

std::vector<PlacedLabel> MapViewLabels(const MapScene& scene, const ViewerOptions& options,
                                       MapViewpoint viewpoint) {
  return LabelsIn(scene, MapViewCamera(scene, options, viewpoint), LegendBox(LegendOf(scene)));
}

}  // namespace ocg
