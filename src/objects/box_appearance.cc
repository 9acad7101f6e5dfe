#include "ocg/objects/box_appearance.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ocg {
namespace {

Box2 Shrunk(const Box2& box, double share) {
  const Eigen::Vector2d centre = box.Centre();
  const double half_width = 0.5 * share * box.Width(), half_height = 0.5 * share * box.Height();
  return {centre.x() - half_width, centre.y() - half_height, centre.x() + half_width,
          centre.y() + half_height};
}

bool Inside(const Box2& box, const Eigen::Vector2d& pixel) {
  return pixel.x() >= box.x0 && pixel.x() < box.x1 && pixel.y() >= box.y0 && pixel.y() < box.y1;
}

// Whether a world point lies inside the cuboid grown by margin on every side.
bool InGrownCuboid(const Cuboid& cuboid, const Eigen::Matrix3d& R_wg, double margin,
                   const Eigen::Vector3d& point) {
  const Eigen::Matrix3d R_wc = R_wg * Eigen::AngleAxisd(cuboid.yaw, Eigen::Vector3d::UnitZ());
  const Eigen::Vector3d local = R_wc.transpose() * (point - cuboid.centre);
  return (local.cwiseAbs() - 0.5 * cuboid.size).maxCoeff() <= margin;
}

// At most count of items, spread evenly (all when there are fewer).
template <typename T>
std::vector<T> SpreadEvenly(const std::vector<T>& items, int count) {
  if (static_cast<int>(items.size()) <= count) return items;
  std::vector<T> kept;
  for (int i = 0; i < count; ++i)
    kept.push_back(
        items[items.size() * static_cast<std::size_t>(i) / static_cast<std::size_t>(count)]);
  return kept;
}

}  // namespace

void BoxAppearanceOptions::Check() const {
  if (!(box_share > 0.0 && box_share <= 1.0))
    throw std::invalid_argument("box_appearance.box_share must be in (0, 1]");
  if (!(cuboid_margin >= 0.0))
    throw std::invalid_argument("box_appearance.cuboid_margin must be at least 0");
  if (max_keyframes < 1)
    throw std::invalid_argument("box_appearance.max_keyframes must be at least 1");
}

std::vector<Descriptor> BoxDescriptors(const std::vector<FrameBox>& boxes, const Cuboid& cuboid,
                                       const Eigen::Matrix3d& R_wg,
                                       const KeyframeFeatureMap& keyframes,
                                       const BoxAppearanceOptions& options) {
  std::vector<std::pair<const FrameBox*, const KeyframeFeatures*>> at_keyframes;
  for (const FrameBox& sighting : boxes) {
    const auto keyframe = keyframes.find(sighting.frame);
    if (keyframe != keyframes.end()) at_keyframes.emplace_back(&sighting, &keyframe->second);
  }
  const double margin = options.cuboid_margin * cuboid.size.maxCoeff();
  std::vector<Descriptor> descriptors;
  for (const auto& [sighting, keyframe] : SpreadEvenly(at_keyframes, options.max_keyframes)) {
    const Box2 box = Shrunk(sighting->box, options.box_share);
    for (std::size_t i = 0; i < keyframe->pixels.size(); ++i) {
      if (!Inside(box, keyframe->pixels[i])) continue;
      const std::optional<Eigen::Vector3d>& point = keyframe->points[i];
      if (point && !InGrownCuboid(cuboid, R_wg, margin, *point)) continue;
      descriptors.push_back(keyframe->descriptors[i]);
    }
  }
  return descriptors;
}

std::vector<Descriptor> PlaceDescriptors(const Cuboid& cuboid, const Eigen::Matrix3d& R_wg,
                                         const PinholeCamera& camera,
                                         const std::vector<const KeyframeFeatures*>& keyframes,
                                         const BoxAppearanceOptions& options) {
  std::vector<std::pair<const KeyframeFeatures*, Box2>> views;
  for (const KeyframeFeatures* keyframe : keyframes) {
    const std::optional<Box2> box = ProjectCuboid(cuboid, R_wg, keyframe->T_cw, camera);
    if (box) views.emplace_back(keyframe, Shrunk(*box, options.box_share));
  }
  std::vector<Descriptor> descriptors;
  for (const auto& [keyframe, box] : SpreadEvenly(views, options.max_keyframes)) {
    for (std::size_t i = 0; i < keyframe->pixels.size(); ++i) {
      if (Inside(box, keyframe->pixels[i])) descriptors.push_back(keyframe->descriptors[i]);
    }
  }
  return descriptors;
}

std::vector<Descriptor> WithoutBackground(const std::vector<Descriptor>& object,
                                          const std::vector<Descriptor>& background,
                                          int max_distance) {
  std::vector<Descriptor> kept;
  for (const Descriptor& descriptor : object) {
    const bool seen =
        std::any_of(background.begin(), background.end(), [&](const Descriptor& other) {
          return HammingDistance(descriptor, other) <= max_distance;
        });
    if (!seen) kept.push_back(descriptor);
  }
  return kept;
}

}  // namespace ocg
