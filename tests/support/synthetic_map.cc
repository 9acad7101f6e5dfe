#include "synthetic_map.h"

namespace ocg::testing {

KeyFramePtr SyntheticKeyFrame(const SyntheticScene& scene, int frame, const SE3& T_cw,
                              KeyFrameId id, const Vocabulary& vocabulary) {
  auto keyframe = std::make_shared<KeyFrame>();
  keyframe->id = id;
  keyframe->frame_id = static_cast<std::uint64_t>(frame);
  keyframe->timestamp = scene.timestamps[static_cast<std::size_t>(frame)];
  keyframe->timestamp_text = std::to_string(keyframe->timestamp);
  keyframe->T_cw = T_cw;
  ExtractedFeatures& features = keyframe->features;
  for (const SyntheticProjection& projection : scene.projections[static_cast<std::size_t>(frame)]) {
    features.keypoints.emplace_back(static_cast<float>(projection.pixel.x()),
                                    static_cast<float>(projection.pixel.y()), 31.0f, 0.0f, 1.0f, 0);
    features.undistorted.push_back(projection.pixel);
    features.descriptors.push_back(scene.descriptors[static_cast<std::size_t>(projection.point)]);
  }
  features.grid = FeatureGrid(features.undistorted, features.Levels(),
                              UndistortedImageBounds(scene.options.camera));
  vocabulary.Transform(features.descriptors, &keyframe->bow, &keyframe->feature_vector);
  keyframe->points.assign(features.size(), nullptr);
  return keyframe;
}

int FeatureOfPoint(const SyntheticScene& scene, int frame, int point) {
  const auto& projections = scene.projections[static_cast<std::size_t>(frame)];
  for (std::size_t i = 0; i < projections.size(); ++i) {
    if (projections[i].point == point) return static_cast<int>(i);
  }
  return -1;
}

MapPointPtr AddSyntheticPoint(const SyntheticScene& scene, int point,
                              const Eigen::Vector3d& position,
                              const std::vector<KeyFramePtr>& observers,
                              const ScalePyramid& pyramid, Map* map) {
  auto map_point = std::make_shared<MapPoint>();
  map_point->id = map->NextMapPointId();
  map_point->position = position;
  map_point->descriptor = scene.descriptors[static_cast<std::size_t>(point)];
  map->Add(map_point);
  for (const KeyFramePtr& keyframe : observers) {
    const int feature = FeatureOfPoint(scene, static_cast<int>(keyframe->frame_id), point);
    if (feature < 0) continue;
    if (map_point->observations.empty())
      map_point->reference = map_point->first_keyframe = keyframe->id;
    map->AddObservation(keyframe, feature, map_point);
  }
  map->UpdatePointGeometry(map_point, pyramid);
  map->UpdatePointDescriptor(map_point);
  return map_point;
}

void ConnectSyntheticMap(Map* map, BowDatabase* database) {
  for (const auto& [id, keyframe] : map->keyframes()) {
    map->UpdateConnections(keyframe);
    database->Add(static_cast<int>(id), keyframe->bow);
  }
}

}  // namespace ocg::testing
