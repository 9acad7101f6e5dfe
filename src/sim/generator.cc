#include "ocg/sim/generator.h"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "ocg/core/coco.h"
#include "ocg/core/file_io.h"
#include "ocg/core/logging.h"
#include "ocg/io/trajectory.h"
#include "ocg/ocg/replay_format.h"
#include "ocg/sim/detector.h"
#include "ocg/sim/scene_io.h"
#include "ocg/sim/texture.h"

namespace ocg::sim {
namespace {

namespace fs = std::filesystem;

constexpr double kSensorNoise = 2.0;  // grey levels, std

SE3 PoseOf(const PlacedPose& pose) {
  return SE3(Eigen::Matrix3d(Eigen::AngleAxisd(pose.yaw, Eigen::Vector3d::UnitZ())), pose.centre);
}

Mesh ShapeMesh(Shape shape, const Eigen::Vector3d& size) {
  const float uv_scale = 1.0f / static_cast<float>(size.maxCoeff());
  if (shape == Shape::kCylinder) {
    return Mesh::Cylinder(static_cast<float>(size.x() / 2), static_cast<float>(size.z()), 32,
                          uv_scale);
  }
  return Mesh::Box(size.cast<float>(), uv_scale);
}

// Corners of an object's oriented box projected (clipped to a near plane), and the share
// of their convex hull inside the image.
struct Projection {
  double hull_area = 0.0;
  double hull_area_inside = 0.0;
};

Projection ProjectBox(const SceneObject& object, const PlacedPose& pose, const SE3& T_cw,
                      const PinholeCamera& camera) {
  std::vector<cv::Point2f> points;
  const SE3 T_wo = PoseOf(pose);
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d local((corner & 1 ? 0.5 : -0.5) * object.size.x(),
                                (corner & 2 ? 0.5 : -0.5) * object.size.y(),
                                (corner & 4 ? 0.5 : -0.5) * object.size.z());
    Eigen::Vector3d p = T_cw * (T_wo * local);
    p.z() = std::max(p.z(), 0.05);
    const Eigen::Vector2d pixel =
        camera.HasDistortion() ? camera.Project(p) : camera.ProjectUndistorted(p);
    points.emplace_back(static_cast<float>(pixel.x()), static_cast<float>(pixel.y()));
  }
  std::vector<cv::Point2f> hull;
  cv::convexHull(points, hull);
  Projection projection;
  projection.hull_area = cv::contourArea(hull);
  const std::vector<cv::Point2f> image = {{-0.5f, -0.5f},
                                          {camera.width - 0.5f, -0.5f},
                                          {camera.width - 0.5f, camera.height - 0.5f},
                                          {-0.5f, camera.height - 0.5f}};
  std::vector<cv::Point2f> inside;
  projection.hull_area_inside = cv::intersectConvexConvex(hull, image, inside);
  return projection;
}

// How the realistic detector sees an object (detector.h). The blur comes from the scene's
// camera path around t: rotation moves every pixel by about f * angle, translation by
// f * d / distance.
ViewingConditions ConditionsOf(const Scene& scene, const SceneObject& object,
                               const PlacedPose& pose, const SE3& T_cw, double t, double occlusion,
                               double truncation, double box_pixels) {
  ViewingConditions c;
  const Eigen::Vector3d camera_centre = T_cw.Inverse().translation();
  const Eigen::Vector3d line_of_sight = camera_centre - pose.centre;
  c.distance = line_of_sight.norm();
  c.has_face = object.shape == Shape::kBox;
  // The largest vertical face: its normal is the object's y axis when x is the longer side.
  const Eigen::Vector3d face_normal =
      Eigen::AngleAxisd(pose.yaw, Eigen::Vector3d::UnitZ()) *
      (object.size.x() >= object.size.y() ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitX());
  const Eigen::Vector3d horizontal(line_of_sight.x(), line_of_sight.y(), 0.0);
  c.view_angle = horizontal.norm() > 1e-9
                     ? std::acos(std::min(1.0, std::abs(face_normal.dot(horizontal.normalized()))))
                     : 0.0;
  constexpr double kStep = 0.005;
  const SE3 motion =
      CameraPoseAt(scene, t + kStep) * CameraPoseAt(scene, std::max(t - kStep, 0.0)).Inverse();
  const double focal = std::max(scene.camera.fx, scene.camera.fy);
  const double pixels_per_second =
      focal *
      (LogSO3(motion.rotation()).norm() + motion.translation().norm() / std::max(c.distance, 0.1)) /
      (t >= kStep ? 2 * kStep : t + kStep);
  c.blur_pixels = pixels_per_second * scene.noise.realistic.exposure_ms / 1000.0;
  c.occlusion = occlusion;
  c.truncation = truncation;
  c.box_pixels = box_pixels;
  return c;
}

// Id of walker pixels in WalkerCoverage's id pass: above any object id, within the 24 bits
// the id pass encodes.
constexpr std::uint32_t kWalkerPixelId = 0xfffffe;

void AppendMesh(Mesh& to, const Mesh& part) {
  const auto offset = static_cast<std::uint32_t>(to.vertices.size());
  to.vertices.insert(to.vertices.end(), part.vertices.begin(), part.vertices.end());
  for (const std::uint32_t index : part.triangles) to.triangles.push_back(index + offset);
}

// A person in its own frame (x forward, y to its left, z up, feet at z = 0), `height`
// tall: two legs, a torso, two arms hanging beside it and a head; about 0.62 m across the
// arms (Walker::Radius), 0.24 m deep. The texture spans the height.
Mesh WalkerBody(double height) {
  const double s = height / 1.75;
  const float uv_scale = static_cast<float>(1.0 / height);
  Mesh body;
  auto box = [&](const Eigen::Vector3d& size, const Eigen::Vector3d& centre) {
    AppendMesh(body, Mesh::Box((s * size).cast<float>(), uv_scale)
                         .Transformed(SE3(Eigen::Matrix3d::Identity(), s * centre)));
  };
  for (const double side : {-1.0, 1.0}) {
    box({0.16, 0.15, 0.82}, {0.0, side * 0.1, 0.41});    // leg
    box({0.10, 0.09, 0.60}, {0.0, side * 0.265, 1.13});  // arm
  }
  box({0.24, 0.44, 0.62}, {0.0, 0.0, 1.13});  // torso
  AppendMesh(body,
             Mesh::Cylinder(static_cast<float>(s * 0.1), static_cast<float>(s * 0.28), 16, uv_scale)
                 .Transformed(SE3(Eigen::Matrix3d::Identity(),
                                  Eigen::Vector3d(0.0, 0.0, s * 1.61))));  // head
  return body;
}

}  // namespace

// ---------------------------------------------------------------- SceneRenderer

SceneRenderer::SceneRenderer(const Scene& scene)
    : scene_(scene),
      sensor_(scene.look.realistic()
                  ? std::make_unique<CameraSensor>(scene.look, OutputCamera(scene), scene.seed)
                  : nullptr),
      render_camera_(sensor_ ? sensor_->maps().pinhole : scene.camera),
      renderer_(render_camera_.width, render_camera_.height) {
  const bool realistic = scene.look.realistic();
  const Eigen::Vector3f light = scene.light_direction.cast<float>();
  for (const Furniture& item : scene.furniture) {
    DrawItem draw;
    const double largest = item.size.maxCoeff();
    draw.mesh = Mesh::Box(item.size.cast<float>(), static_cast<float>(1.0 / largest))
                    .Transformed(PoseOf({0.0, true, item.centre, item.yaw}));
    // 1024 texels suffice for walls: their features are centimetres (texture.h), and 2048
    // would cost 30 % of the rendering time.
    const int texture_size = largest > 1.2 ? 1024 : 512;
    draw.texture = renderer_.AddTexture(
        realistic ? MakeMaterialTexture(FurnitureMaterial(item.name), item.texture_seed,
                                        texture_size, largest)
                  : MakeTexture(item.texture_seed, texture_size, largest));
    draw.colour = Eigen::Vector3f::Ones();
    Renderer::Shade(draw, light, static_cast<float>(scene.ambient));
    furniture_.push_back(std::move(draw));
  }
  for (const SceneObject& object : scene.objects) {
    const double span = object.size.maxCoeff();
    object_textures_[object.id] =
        renderer_.AddTexture(realistic ? MakeMaterialTexture(ObjectMaterial(object.class_id),
                                                             object.texture_seed, 256, span)
                                       : MakeTexture(object.texture_seed, 256, span));
    auto& items = object_items_[object.id];
    for (const PlacedPose& pose : object.history) items.push_back(MakeObjectItem(object, pose));
  }
  for (const Walker& walker : scene.walkers) {
    walker_textures_[walker.id] = renderer_.AddTexture(
        realistic ? MakeMaterialTexture(Material::kCloth, walker.texture_seed, 256, walker.height)
                  : MakeTexture(walker.texture_seed, 256, walker.height));
    walker_bodies_[walker.id] = WalkerBody(walker.height);
  }
}

DrawItem SceneRenderer::MakeObjectItem(const SceneObject& object, const PlacedPose& pose) {
  DrawItem draw;
  draw.mesh = ShapeMesh(object.shape, object.size).Transformed(PoseOf(pose));
  draw.texture = object_textures_.at(object.id);
  draw.colour = Eigen::Vector3f::Ones();
  draw.id = static_cast<std::uint32_t>(object.id);
  Renderer::Shade(draw, scene_.light_direction.cast<float>(), static_cast<float>(scene_.ambient));
  return draw;
}

void SceneRenderer::AppendPose(int object_id, const PlacedPose& pose) {
  SceneObject* object = scene_.FindObject(object_id);
  if (object == nullptr) throw std::invalid_argument("no object " + std::to_string(object_id));
  object->history.push_back(pose);
  object_items_.at(object_id).push_back(MakeObjectItem(*object, pose));
}

void SceneRenderer::PopPose(int object_id) {
  SceneObject* object = scene_.FindObject(object_id);
  if (object == nullptr || object->history.size() < 2)
    throw std::invalid_argument("no scheduled pose of object " + std::to_string(object_id));
  object->history.pop_back();
  object_items_.at(object_id).pop_back();
}

std::vector<const DrawItem*> SceneRenderer::ItemsAt(double t, int skip_object, bool mark_walkers) {
  std::vector<const DrawItem*> items;
  for (const DrawItem& item : furniture_) items.push_back(&item);
  for (const SceneObject& object : scene_.objects) {
    if (object.id == skip_object) continue;
    const std::vector<DrawItem>& poses = object_items_.at(object.id);
    int current = -1;
    for (size_t i = 0; i < object.history.size(); ++i) {
      if (object.history[i].time <= t) current = static_cast<int>(i);
    }
    if (current >= 0 && object.history[static_cast<size_t>(current)].present) {
      items.push_back(&poses[static_cast<size_t>(current)]);
    }
  }
  walker_items_.clear();
  walker_items_.reserve(scene_.walkers.size());  // items points into it
  for (const Walker& walker : scene_.walkers) {
    const std::optional<PlacedPose> pose = walker.PoseAt(t);
    if (!pose) continue;
    DrawItem draw;
    draw.mesh = walker_bodies_.at(walker.id).Transformed(PoseOf(*pose));
    draw.texture = walker_textures_.at(walker.id);
    draw.colour = Eigen::Vector3f::Ones();
    draw.id = mark_walkers ? kWalkerPixelId : 0;
    Renderer::Shade(draw, scene_.light_direction.cast<float>(), static_cast<float>(scene_.ambient));
    walker_items_.push_back(std::move(draw));
    items.push_back(&walker_items_.back());
  }
  return items;
}

cv::Mat SceneRenderer::WalkerMask(double t, const SE3& T_cw) {
  const PinholeCamera output = OutputCamera(scene_);
  if (scene_.walkers.empty()) return cv::Mat::zeros(output.height, output.width, CV_8UC1);
  cv::Mat ids = renderer_.RenderIds(ItemsAt(t, -1, /*mark_walkers=*/true), T_cw, render_camera_);
  if (sensor_) ids = sensor_->Distort(ids);
  return ids == static_cast<int>(kWalkerPixelId);
}

double SceneRenderer::WalkerCoverage(double t, const SE3& T_cw) {
  if (scene_.walkers.empty()) return 0.0;
  const cv::Mat mask = WalkerMask(t, T_cw);
  return static_cast<double>(cv::countNonZero(mask)) / static_cast<double>(mask.total());
}

cv::Mat SceneRenderer::Colour(double t, const SE3& T_cw, std::uint64_t noise_seed) {
  if (sensor_) return RealisticColour(t, T_cw, noise_seed);
  const cv::Mat image = renderer_.RenderColour(ItemsAt(t, -1), T_cw, scene_.camera,
                                               Eigen::Vector3f(0.3f, 0.3f, 0.3f));
  // Sensor noise: a window of a pre-drawn noise tile at a seeded offset (drawing a
  // million Gaussian samples per frame would cost more than the rendering).
  if (noise_tile_.empty()) {
    noise_tile_.create(2 * image.rows, 2 * image.cols, CV_16SC3);
    cv::RNG(scene_.seed)
        .fill(noise_tile_, cv::RNG::NORMAL, cv::Scalar::all(0), cv::Scalar::all(kSensorNoise));
  }
  const int dx = static_cast<int>(noise_seed % static_cast<std::uint64_t>(image.cols));
  const int dy = static_cast<int>((noise_seed >> 20) % static_cast<std::uint64_t>(image.rows));
  cv::Mat noisy;
  cv::add(image, noise_tile_(cv::Rect(dx, dy, image.cols, image.rows)), noisy, cv::noArray(),
          CV_8UC3);
  return noisy;
}

cv::Mat SceneRenderer::RealisticColour(double t, const SE3& T_cw, std::uint64_t noise_seed) {
  // The camera's motion around t, from the path, applied to T_cw.
  const SE3 T_wc_path = CameraPoseAt(scene_, t).Inverse();
  auto pose_at = [&](double offset) { return CameraPoseAt(scene_, t + offset) * T_wc_path * T_cw; };
  // Image motion: rotation moves every pixel by about f * angle, translation by f * d / z
  // with z a typical distance to the desk's objects from the paths.
  constexpr double kStep = 0.005, kNearSurface = 1.0;
  const SE3 motion = pose_at(kStep) * pose_at(-kStep).Inverse();
  const double focal = std::max(scene_.camera.fx, scene_.camera.fy);
  const double pixels_per_second =
      focal * (LogSO3(motion.rotation()).norm() + motion.translation().norm() / kNearSurface) /
      (2 * kStep);
  const std::vector<double> times = sensor_->SampleTimes(pixels_per_second);
  const std::vector<const DrawItem*> items = ItemsAt(t, -1);
  std::vector<cv::Mat> renders;
  for (double offset : times) {
    renders.push_back(renderer_.RenderColour(items, pose_at(offset), render_camera_,
                                             Eigen::Vector3f(0.3f, 0.3f, 0.3f)));
  }
  return sensor_->Record(renders, times, t, noise_seed);
}

cv::Mat SceneRenderer::Ids(double t, const SE3& T_cw, cv::Mat* depth) {
  cv::Mat ids = renderer_.RenderIds(ItemsAt(t, -1), T_cw, render_camera_, depth);
  if (sensor_) {
    ids = sensor_->Distort(ids);
    if (depth != nullptr) *depth = sensor_->Distort(*depth);
  }
  // Furniture carries id 0 already (DrawItem default), so only objects remain.
  return ids;
}

int SceneRenderer::VisiblePixels(int object_id, const PlacedPose& pose, double t, const SE3& T_cw) {
  std::vector<const DrawItem*> items = ItemsAt(t, object_id);
  const SceneObject* object = scene_.FindObject(object_id);
  if (object == nullptr) throw std::invalid_argument("no object " + std::to_string(object_id));
  const DrawItem probe = MakeObjectItem(*object, pose);
  items.push_back(&probe);
  // With a distorting lens the pinhole render is wider than the image: a conservative
  // count, so changes stay unseen.
  const cv::Mat ids = renderer_.RenderIds(items, T_cw, render_camera_);
  return cv::countNonZero(ids == object_id);
}

// ---------------------------------------------------------------- changes

namespace {

// Both places hidden at the frames just before and after time t?
bool ChangeIsUnseen(SceneRenderer& renderer, int object_id, const PlacedPose& before,
                    const PlacedPose& after, double t) {
  const Scene& scene = renderer.scene();
  const double step = 1.0 / scene.fps;
  for (double when : {t - step, t, t + step}) {
    if (when < 0) continue;
    const SE3 T_cw = CameraPoseAt(scene, when);
    if (before.present && renderer.VisiblePixels(object_id, before, when, T_cw) > 0) return false;
    if (after.present && renderer.VisiblePixels(object_id, after, when, T_cw) > 0) return false;
  }
  return true;
}

// Every change ScheduleMoves added (history entries from first_added[id] on) at a time
// from `from` on still unseen, with every change now in place?
bool ScheduledChangesUnseen(const Scene& scene, SceneRenderer& renderer,
                            const std::map<int, std::size_t>& first_added, double from) {
  for (const SceneObject& object : scene.objects) {
    for (std::size_t i = std::max<std::size_t>(1, first_added.at(object.id));
         i < object.history.size(); ++i) {
      if (object.history[i].time >= from &&
          !ChangeIsUnseen(renderer, object.id, object.history[i - 1], object.history[i],
                          object.history[i].time)) {
        return false;
      }
    }
  }
  return true;
}

// Schedules one change at the first unseen moment from its earliest time (careful: a moment
// at which every change already scheduled after it stays unseen too); false when none is.
bool ScheduleMove(Scene& scene, const PlannedMove& move, SceneRenderer& renderer,
                  const std::map<int, std::size_t>* careful) {
  SceneObject* object = scene.FindObject(move.object_id);
  if (object == nullptr)
    throw std::runtime_error("planned move of unknown object " + std::to_string(move.object_id));
  const PlacedPose before = object->history.back();
  PlacedPose after = before;
  after.present = !move.removal;
  after.centre = move.new_centre;
  after.yaw = move.new_yaw;
  // Every third frame is a candidate; the check itself covers the frames around it.
  const int first = static_cast<int>(std::ceil(move.earliest * scene.fps));
  for (int frame = first; frame < scene.FrameCount() - 1; frame += 3) {
    const double t = (frame + 0.5) / scene.fps;  // between two frames
    if (t <= before.time || !ChangeIsUnseen(renderer, object->id, before, after, t)) continue;
    after.time = t;
    object->history.push_back(after);
    renderer.AppendPose(object->id, after);
    // The change shows in the checks of changes up to a frame and a half before it.
    if (careful == nullptr ||
        ScheduledChangesUnseen(scene, renderer, *careful, t - 1.5 / scene.fps)) {
      return true;
    }
    object->history.pop_back();
    renderer.PopPose(object->id);
  }
  return false;
}

}  // namespace

void ScheduleMoves(Scene& scene, const std::vector<PlannedMove>& moves, SceneRenderer& renderer) {
  std::map<int, std::size_t> first_added;  // per object, its history's size before
  for (const SceneObject& object : scene.objects) first_added[object.id] = object.history.size();
  // The first pass, as scenes have always been made: each change at its first unseen
  // moment given the changes listed before it.
  bool scheduled = true;
  for (const PlannedMove& move : moves) {
    scheduled = ScheduleMove(scene, move, renderer, nullptr);
    if (!scheduled) break;
  }
  if (scheduled && ScheduledChangesUnseen(scene, renderer, first_added, 0.0)) return;
  // It failed: start again with the careful pass.
  for (SceneObject& object : scene.objects) {
    while (object.history.size() > first_added.at(object.id)) {
      object.history.pop_back();
      renderer.PopPose(object.id);
    }
  }
  for (const PlannedMove& move : moves) {
    bool done = ScheduleMove(scene, move, renderer, &first_added);
    for (const PlannedMove& alternative : move.alternatives) {
      if (done) break;
      const SceneObject* object = scene.FindObject(alternative.object_id);
      const bool changed =
          object == nullptr || object->history.size() > first_added.at(alternative.object_id);
      if (!changed) done = ScheduleMove(scene, alternative, renderer, &first_added);
    }
    if (!done) {
      throw std::runtime_error(
          "no time after " + std::to_string(move.earliest) + " s at which object " +
          std::to_string(move.object_id) + " can change unseen" +
          (move.alternatives.empty()
               ? std::string()
               : ", nor any of its " + std::to_string(move.alternatives.size()) + " alternatives") +
          " (every change scheduled after it staying unseen)");
    }
  }
}

void ValidateChanges(const Scene& scene, SceneRenderer& renderer) {
  for (const SceneObject& object : scene.objects) {
    for (size_t i = 1; i < object.history.size(); ++i) {
      if (!ChangeIsUnseen(renderer, object.id, object.history[i - 1], object.history[i],
                          object.history[i].time)) {
        throw std::invalid_argument("scene: object " + std::to_string(object.id) +
                                    " changes at t = " + std::to_string(object.history[i].time) +
                                    " s while its old or new place is visible to the camera");
      }
    }
  }
}

// ---------------------------------------------------------------- detections

DetectionModel::DetectionModel(const Scene& scene) : scene_(scene) {
  if (scene.noise.kind == DetectorKind::kRealistic) {
    realistic_.emplace(scene.noise.realistic, scene.duration,
                       SeedMix(scene.seed, scene.noise.realistic.seed));
  }
}

DetectionModel::FrameResult DetectionModel::Detect(const cv::Mat& ids, double t, const SE3& T_cw,
                                                   int frame) {
  const DetectionNoise& noise = scene_.noise;
  std::mt19937_64 rng(SeedMix(scene_.seed, static_cast<std::uint64_t>(frame) + 1));
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> gaussian(0.0, 1.0);
  // Visible pixels and their bounding box, per object.
  struct Stats {
    int pixels = 0;
    int min_x = INT32_MAX, min_y = INT32_MAX, max_x = -1, max_y = -1;
  };
  std::map<int, Stats> stats;
  for (int row = 0; row < ids.rows; ++row) {
    const std::int32_t* line = ids.ptr<std::int32_t>(row);
    for (int column = 0; column < ids.cols; ++column) {
      if (line[column] == 0) continue;
      Stats& s = stats[line[column]];
      ++s.pixels;
      s.min_x = std::min(s.min_x, column);
      s.max_x = std::max(s.max_x, column);
      s.min_y = std::min(s.min_y, row);
      s.max_y = std::max(s.max_y, row);
    }
  }
  FrameResult result;
  const double width = scene_.camera.width, height = scene_.camera.height;
  // Jitters the box's edges (clipped to the image), scores it (score given the jittered
  // box; nullptr: keep its confidence), adds it and, now and then, a duplicate. One
  // generator and distributions for the frame: the independent model's outputs depend on
  // the order of the draws.
  const std::function<double(const Detection&)> keep_score;
  auto add_noisy_box = [&](Detection detection,
                           const std::function<double(const Detection&)>& score) {
    const double jx = noise.box_jitter * detection.width, jy = noise.box_jitter * detection.height;
    double x1 = detection.x + jx * gaussian(rng), y1 = detection.y + jy * gaussian(rng);
    double x2 = detection.x + detection.width + jx * gaussian(rng);
    double y2 = detection.y + detection.height + jy * gaussian(rng);
    x1 = std::clamp(std::round(x1), 0.0, width - 2);
    y1 = std::clamp(std::round(y1), 0.0, height - 2);
    x2 = std::clamp(std::round(x2), x1 + 1, width - 1);
    y2 = std::clamp(std::round(y2), y1 + 1, height - 1);
    detection.x = x1;
    detection.y = y1;
    detection.width = x2 - x1;
    detection.height = y2 - y1;
    if (score) detection.confidence = score(detection);
    result.detections.push_back(detection);
    if (uniform(rng) < noise.duplicate) {
      Detection duplicate = detection;
      duplicate.x =
          std::clamp(detection.x + 0.15 * detection.width * gaussian(rng), 0.0, width - 2);
      duplicate.y =
          std::clamp(detection.y + 0.15 * detection.height * gaussian(rng), 0.0, height - 2);
      duplicate.width = std::max(
          1.0, std::min(detection.width * (0.8 + 0.3 * uniform(rng)), width - 1 - duplicate.x));
      duplicate.height = std::max(
          1.0, std::min(detection.height * (0.8 + 0.3 * uniform(rng)), height - 1 - duplicate.y));
      duplicate.confidence = std::clamp(detection.confidence - 0.2, 0.25, 0.97);
      result.detections.push_back(duplicate);
      ++result.duplicates;
    }
  };
  for (const SceneObject& object : scene_.objects) {
    const auto found = stats.find(object.id);
    if (found == stats.end() || found->second.pixels < noise.min_visible_pixels) {
      missed_last_frame_[object.id] = false;
      continue;
    }
    const Stats& s = found->second;
    ++result.visible;
    result.visible_objects.push_back(object.id);
    Detection detection;
    detection.class_id = object.class_id;
    detection.x = s.min_x;
    detection.y = s.min_y;
    detection.width = s.max_x - s.min_x + 1;
    detection.height = s.max_y - s.min_y + 1;
    if (noise.perfect) {
      detection.confidence = 1.0;
      result.detections.push_back(detection);
      result.detected_objects.push_back(object.id);
      continue;
    }
    const PlacedPose pose = *object.PoseAt(t);
    const Projection projection = ProjectBox(object, pose, T_cw, scene_.camera);
    const double truncation =
        projection.hull_area > 0 ? 1.0 - projection.hull_area_inside / projection.hull_area : 0.0;
    const double occlusion =
        projection.hull_area_inside > 0
            ? std::clamp(1.0 - s.pixels / projection.hull_area_inside, 0.0, 1.0)
            : 0.0;
    if (realistic_) {
      const ViewingConditions conditions = ConditionsOf(
          scene_, object, pose, T_cw, t, occlusion, truncation, detection.width * detection.height);
      const RealisticDetector::Decision decision =
          realistic_->Decide(object.id, object.class_id, conditions, t, frame);
      if (!decision.detected) {
        ++result.missed;
        continue;
      }
      if (decision.class_id != object.class_id) ++result.confused;
      detection.class_id = decision.class_id;
      detection.confidence = decision.confidence;
      add_noisy_box(detection, keep_score);
      result.detected_objects.push_back(object.id);
      continue;
    }
    double miss =
        noise.miss_base + noise.miss_occlusion * occlusion + noise.miss_truncation * truncation;
    if (detection.width * detection.height < noise.small_box_pixels) miss += noise.miss_small;
    if (missed_last_frame_[object.id]) miss = std::max(miss, noise.burst_continue);
    if (uniform(rng) < std::min(miss, 1.0)) {
      missed_last_frame_[object.id] = true;
      ++result.missed;
      continue;
    }
    missed_last_frame_[object.id] = false;
    if (uniform(rng) < noise.confusion && ConfusedClass(object.class_id) != object.class_id) {
      detection.class_id = ConfusedClass(object.class_id);
      ++result.confused;
    }
    // Calibrated on the real YOLO detections of TUM fr3 long_office (mean 0.63, 1 % above
    // 0.9): fully visible objects score about 0.7, occlusion and truncation lower it. The
    // independent model draws the score after the jitter: kept so its outputs stay the same.
    add_noisy_box(detection, [&](const Detection& box) {
      const double small = box.width * box.height < noise.small_box_pixels ? 0.1 : 0.0;
      return std::clamp(0.72 - 0.3 * occlusion - 0.25 * truncation - small + 0.1 * gaussian(rng),
                        0.25, 0.97);
    });
    result.detected_objects.push_back(object.id);
  }
  if (!noise.perfect) {
    std::poisson_distribution<int> false_positives(noise.false_positives_per_frame);
    for (int i = false_positives(rng); i > 0; --i) {
      Detection ghost;
      ghost.class_id =
          scene_.objects.empty() ? 41 : scene_.objects[rng() % scene_.objects.size()].class_id;
      ghost.width = std::round(30 + 120 * uniform(rng));
      ghost.height = std::round(30 + 120 * uniform(rng));
      ghost.x = std::round(uniform(rng) * (width - ghost.width - 1));
      ghost.y = std::round(uniform(rng) * (height - ghost.height - 1));
      ghost.confidence = 0.25 + 0.3 * uniform(rng);
      result.detections.push_back(ghost);
      ++result.false_positives;
    }
  }
  return result;
}

// ---------------------------------------------------------------- writing

std::int64_t OracleMapId(int object_id, std::size_t pose_index) {
  return static_cast<std::int64_t>(object_id) * kOracleIdStride +
         static_cast<std::int64_t>(pose_index);
}

std::string OracleObservation(const Scene& scene, std::int64_t keyframe, double t, const SE3& T_cw,
                              const std::vector<int>& detected_objects) {
  KeyframeObservation observation;
  observation.keyframe_id = keyframe;
  observation.timestamp = scene.time_origin + t;
  observation.T_cw = T_cw;
  observation.camera = OutputCamera(scene);
  for (int id : detected_objects) {
    const SceneObject& object = *scene.FindObject(id);
    std::size_t index = 0;
    for (std::size_t i = 0; i < object.history.size(); ++i) {
      if (object.history[i].time <= t) index = i;
    }
    const std::int64_t map_id = OracleMapId(id, index);
    observation.observed.push_back(map_id);
    ObjectGeometryUpdate& update = observation.updates[map_id];
    update.centroid = object.history[index].centre;
    update.size = object.size;
    update.class_id = object.class_id;
  }
  return ObservationToJson(observation);
}

std::string FrameTimestamp(const Scene& scene, int frame) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.6f", scene.time_origin + frame / scene.fps);
  return buffer;
}

namespace {

nlohmann::json PlacementJson(const PlacedPose& pose, double time) {
  return {{"time", time},
          {"present", pose.present},
          {"centre", {pose.centre.x(), pose.centre.y(), pose.centre.z()}},
          {"yaw", pose.yaw}};
}

std::string StatusOf(const std::vector<PlacedPose>& history) {
  if (history.size() < 2) return "static";
  const bool starts = history.front().present;
  const bool ends = history.back().present;
  return starts && ends ? "moved" : starts ? "removed" : "added";
}

}  // namespace

std::string ObjectsGroundTruthJson(const Scene& scene, const FramesInView* frames_in_view,
                                   double end_time) {
  nlohmann::json objects = nlohmann::json::array();
  nlohmann::json between = nlohmann::json::array();
  for (const SceneObject& object : scene.objects) {
    // A later visit's history starts with the previous visit's last pose, so the places
    // left between the visits are outdated places for `ocg_eval objects`.
    std::vector<PlacedPose> combined;
    nlohmann::json history = nlohmann::json::array();
    if (object.before_session) {
      combined.push_back(*object.before_session);
      history.push_back(PlacementJson(*object.before_session, scene.session.previous_end));
      history.back()["session"] = scene.session.index - 1;
      const std::vector<PlacedPose> visit = {*object.before_session, object.history.front()};
      const PlacedPose& after = object.history.front();
      between.push_back(
          {{"id", object.id},
           {"class", CocoClassName(object.class_id)},
           {"type", StatusOf(visit)},
           {"before", object.before_session->present
                          ? PlacementJson(*object.before_session, scene.session.previous_end)
                          : nlohmann::json(nullptr)},
           {"after",
            after.present ? PlacementJson(after, scene.time_origin) : nlohmann::json(nullptr)}});
    }
    const std::vector<int>* in_view = nullptr;
    if (frames_in_view != nullptr) {
      const auto found = frames_in_view->find(object.id);
      if (found != frames_in_view->end()) in_view = &found->second;
    }
    for (std::size_t i = 0; i < object.history.size(); ++i) {
      const PlacedPose& pose = object.history[i];
      if (i > 0 && pose.time > end_time) break;  // history is in time order
      combined.push_back(pose);
      history.push_back(PlacementJson(pose, scene.time_origin + pose.time));
      if (frames_in_view != nullptr) {
        history.back()["frames_in_view"] =
            in_view != nullptr && i < in_view->size() ? (*in_view)[i] : 0;
      }
    }
    objects.push_back({{"id", object.id},
                       {"class_id", object.class_id},
                       {"class", CocoClassName(object.class_id)},
                       {"shape", object.shape == Shape::kBox ? "box" : "cylinder"},
                       {"size", {object.size.x(), object.size.y(), object.size.z()}},
                       {"status", StatusOf(combined)},
                       {"history", history}});
  }
  nlohmann::json root = {{"scene", scene.name},
                         {"seed", scene.seed},
                         {"time_origin", scene.time_origin},
                         {"objects", objects}};
  if (scene.session.index > 0) {
    root["session"] = {{"index", scene.session.index},
                       {"previous", scene.session.previous},
                       {"previous_end", scene.session.previous_end},
                       {"changes", between}};
  }
  return root.dump(1) + "\n";
}

std::string CameraSettingsYaml(const Scene& scene) {
  const PinholeCamera& c = scene.camera;
  char text[640];
  if (scene.look.realistic()) {
    const PinholeCamera lens = OutputCamera(scene);
    std::snprintf(text, sizeof(text),
                  "# Settings for the rendered camera of the synthetic scene '%s' (realistic look: "
                  "the images are distorted with these coefficients).\n"
                  "Camera:\n  fx: %.6f\n  fy: %.6f\n  cx: %.6f\n  cy: %.6f\n"
                  "  k1: %.6f\n  k2: %.6f\n  p1: %.6f\n  p2: %.6f\n  k3: %.6f\n"
                  "  width: %d\n  height: %d\n  fps: %.3f\n  RGB: 0\n",
                  scene.name.c_str(), c.fx, c.fy, c.cx, c.cy, lens.k1, lens.k2, lens.p1, lens.p2,
                  lens.k3, c.width, c.height, scene.fps);
    return text;
  }
  std::snprintf(text, sizeof(text),
                "# Settings for the rendered camera of the synthetic scene '%s' (ideal pinhole).\n"
                "Camera:\n  fx: %.6f\n  fy: %.6f\n  cx: %.6f\n  cy: %.6f\n"
                "  k1: 0\n  k2: 0\n  p1: 0\n  p2: 0\n  k3: 0\n"
                "  width: %d\n  height: %d\n  fps: %.3f\n  RGB: 0\n",
                scene.name.c_str(), c.fx, c.fy, c.cx, c.cy, c.width, c.height, scene.fps);
  return text;
}

namespace {

// Adds one to the placement each visible object has at time t (its last history entry
// not after t).
void CountFramesInView(const Scene& scene, double t, const std::vector<int>& visible_objects,
                       FramesInView* frames_in_view) {
  for (const int id : visible_objects) {
    const SceneObject* object = scene.FindObject(id);
    if (object == nullptr || object->history.empty()) continue;
    std::size_t placement = 0;
    for (std::size_t i = 0; i < object->history.size(); ++i) {
      if (object->history[i].time <= t) placement = i;
    }
    std::vector<int>& counts = (*frames_in_view)[id];
    counts.resize(object->history.size(), 0);
    ++counts[placement];
  }
}

// Renders and writes every file of the sequence into folder.
GenerationStats WriteSequence(SceneRenderer& renderer, const std::string& staging,
                              const GeneratorOptions& options) {
  const Scene& scene = renderer.scene();
  ValidateChanges(scene, renderer);
  DetectionModel detector(scene);
  const int frames = options.max_frames > 0 ? std::min(options.max_frames, scene.FrameCount())
                                            : scene.FrameCount();
  GenerationStats stats;
  std::string rgb_list =
      "# color images\n# synthetic scene '" + scene.name + "'\n# timestamp filename\n";
  std::string depth_list = "# depth maps\n# timestamp filename\n";
  std::string exposure_list =
      "# exposure of each frame (realistic look)\n# timestamp exposure_ms gain\n";
  std::string walker_list =
      "# walkers in each frame: share of the image they cover, how many are in the room\n"
      "# timestamp coverage walkers\n";
  std::vector<StampedPose> groundtruth;
  std::string oracle;
  FramesInView frames_in_view;
  const auto start = std::chrono::steady_clock::now();
  ProgressLine progress("frames", static_cast<std::size_t>(frames));
  // Huffman-only deflate: sensor noise defeats string matching, so this is both the
  // fastest and (nearly) the smallest choice for rendered frames.
  const std::vector<int> png_options = {cv::IMWRITE_PNG_COMPRESSION, 1, cv::IMWRITE_PNG_STRATEGY,
                                        cv::IMWRITE_PNG_STRATEGY_HUFFMAN_ONLY};
  for (int frame = 0; frame < frames; ++frame) {
    const double t = scene.TimeOfFrame(frame);
    const std::string stamp = FrameTimestamp(scene, frame);
    const SE3 T_cw = CameraPoseAt(scene, t);
    auto lap = std::chrono::steady_clock::now();
    auto stage = [&lap](double& total) {
      const auto now = std::chrono::steady_clock::now();
      total += std::chrono::duration<double>(now - lap).count();
      lap = now;
    };
    cv::Mat depth;
    if (options.write_images) {
      if (renderer.sensor() != nullptr) {
        char line[96];
        std::snprintf(line, sizeof(line), "%s %.3f %.3f\n", stamp.c_str(),
                      renderer.sensor()->exposure_ms(), renderer.sensor()->gain());
        exposure_list += line;
      }
      const cv::Mat colour =
          renderer.Colour(t, T_cw, SeedMix(scene.seed, static_cast<std::uint64_t>(frame)));
      stage(stats.colour_seconds);
      if (!cv::imwrite(staging + "/rgb/" + stamp + ".png", colour, png_options)) {
        throw FileError("cannot write '" + staging + "/rgb/" + stamp + ".png'");
      }
      rgb_list += stamp + " rgb/" + stamp + ".png\n";
      stage(stats.write_seconds);
    }
    const cv::Mat ids = renderer.Ids(t, T_cw, options.write_depth ? &depth : nullptr);
    stage(stats.ids_seconds);
    if (options.write_depth) {
      cv::Mat depth16;
      depth.convertTo(depth16, CV_16UC1, 5000.0);  // TUM: 5000 units per metre
      cv::imwrite(staging + "/depth/" + stamp + ".png", depth16, png_options);
      depth_list += stamp + " depth/" + stamp + ".png\n";
    }
    stage(stats.write_seconds);
    const DetectionModel::FrameResult detections = detector.Detect(ids, t, T_cw, frame);
    stage(stats.detect_seconds);
    WriteFile(staging + "/detections/" + stamp + ".txt",
              FormatEaoDetections(detections.detections));
    stage(stats.write_seconds);
    stats.detections += detections.detections.size();
    stats.visible += static_cast<std::size_t>(detections.visible);
    stats.missed += static_cast<std::size_t>(detections.missed);
    stats.false_positives += static_cast<std::size_t>(detections.false_positives);
    stats.duplicates += static_cast<std::size_t>(detections.duplicates);
    CountFramesInView(scene, t, detections.visible_objects, &frames_in_view);
    if (options.keyframe_interval > 0 && frame % options.keyframe_interval == 0) {
      oracle += OracleObservation(scene, frame / options.keyframe_interval, t, T_cw,
                                  detections.detected_objects) +
                "\n";
    }
    if (!scene.walkers.empty()) {
      const double coverage = renderer.WalkerCoverage(t, T_cw);
      int present = 0;
      for (const Walker& walker : scene.walkers) present += walker.PoseAt(t) ? 1 : 0;
      char line[96];
      std::snprintf(line, sizeof(line), "%s %.4f %d\n", stamp.c_str(), coverage, present);
      walker_list += line;
      stats.walker_frames += coverage > 0 ? 1 : 0;
      stats.walker_quarter_frames += coverage >= 0.25 ? 1 : 0;
      stats.walker_coverage_max = std::max(stats.walker_coverage_max, coverage);
      stage(stats.ids_seconds);
    }
    StampedPose pose;
    pose.timestamp = scene.time_origin + t;
    pose.timestamp_text = stamp;
    pose.T_wc = T_cw.Inverse();
    groundtruth.push_back(pose);
    ++stats.frames;
    progress.Update(static_cast<std::size_t>(frame + 1));
  }
  progress.Finish();
  if (options.write_images) WriteFile(staging + "/rgb.txt", rgb_list);
  if (options.write_depth) WriteFile(staging + "/depth.txt", depth_list);
  if (options.write_images && renderer.sensor() != nullptr)
    WriteFile(staging + "/exposure.txt", exposure_list);
  WriteFileAtomically(
      staging + "/groundtruth.txt",
      "# ground truth trajectory (camera to world)\n# timestamp tx ty tz qx qy qz qw\n" +
          FormatTumTrajectory(groundtruth));
  WriteFile(staging + "/objects_gt.json",
            ObjectsGroundTruthJson(scene, &frames_in_view, scene.TimeOfFrame(frames - 1)));
  if (options.keyframe_interval > 0) WriteFile(staging + "/oracle_observations.jsonl", oracle);
  if (!scene.walkers.empty()) WriteFile(staging + "/walkers.txt", walker_list);
  WriteFile(staging + "/scene.yaml", SceneToYaml(scene));
  WriteFile(staging + "/camera.yaml", CameraSettingsYaml(scene));
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

}  // namespace

GenerationStats Generate(const Scene& scene, const std::string& out_dir,
                         const GeneratorOptions& options) {
  scene.Check();
  SceneRenderer renderer(scene);
  return Generate(renderer, out_dir, options);
}

GenerationStats Generate(SceneRenderer& renderer, const std::string& out_dir,
                         const GeneratorOptions& options) {
  renderer.scene().Check();
  std::error_code error;
  if (fs::exists(out_dir, error) && !fs::is_empty(out_dir, error) && !options.overwrite) {
    throw FileError("output folder '" + out_dir + "' exists and is not empty (use --overwrite)");
  }
  const std::string staging = out_dir + ".partial." + std::to_string(::getpid());
  fs::remove_all(staging, error);
  if (options.write_images) EnsureDirectory(staging + "/rgb");
  EnsureDirectory(staging + "/detections");
  if (options.write_depth) EnsureDirectory(staging + "/depth");

  GenerationStats stats;
  try {
    stats = WriteSequence(renderer, staging, options);
  } catch (...) {
    fs::remove_all(staging, error);  // a failed run leaves nothing behind
    throw;
  }
  if (fs::exists(out_dir, error)) fs::remove_all(out_dir);
  fs::rename(staging, out_dir);
  return stats;
}

}  // namespace ocg::sim
