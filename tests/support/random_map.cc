#include "random_map.h"

#include <algorithm>
#include <random>

namespace ocg::testing {

void FillRandomMap(int keyframes, int features, std::uint64_t seed, Map* map) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const ImageBounds bounds{0.0, 640.0, 0.0, 480.0};
  const int point_count = std::max(1, keyframes * features / 3);
  std::vector<MapPointPtr> points;
  for (int i = 0; i < point_count; ++i) {
    auto point = std::make_shared<MapPoint>();
    point->id = map->NextMapPointId();
    point->position = Eigen::Vector3d(unit(random), unit(random), 2.0 + unit(random));
    for (auto& word : point->descriptor) word = random();
    point->normal = Eigen::Vector3d(unit(random), unit(random), 1.0).normalized();
    point->min_distance = 0.5 + unit(random);
    point->max_distance = 3.0 + unit(random);
    point->first_frame = random() % 1000;
    point->visible = 2 + static_cast<int>(random() % 20);
    point->found = 1 + static_cast<int>(random() % 2);
    points.push_back(point);
    map->Add(point);
  }
  KeyFramePtr previous;
  for (int k = 0; k < keyframes; ++k) {
    auto keyframe = std::make_shared<KeyFrame>();
    keyframe->id = map->NextKeyFrameId();
    keyframe->frame_id = static_cast<std::uint64_t>(3 * k + 1);
    keyframe->timestamp = 0.1 * (3 * k + 1);
    keyframe->timestamp_text = std::to_string(keyframe->timestamp);
    keyframe->T_cw = SE3::Exp((Vector6d() << unit(random), unit(random), unit(random),
                               0.1 * unit(random), 0.1 * unit(random), 0.1 * unit(random))
                                  .finished());
    ExtractedFeatures& f = keyframe->features;
    for (int i = 0; i < features; ++i) {
      const float x = static_cast<float>(640.0 * unit(random));
      const float y = static_cast<float>(480.0 * unit(random));
      const int octave = static_cast<int>(random() % 8);
      f.keypoints.emplace_back(x, y, 31.0f * (1.0f + 0.2f * octave),
                               static_cast<float>(360.0 * unit(random)),
                               static_cast<float>(unit(random)), octave);
      f.undistorted.emplace_back(x + 0.5 * unit(random), y + 0.5 * unit(random));
      Descriptor descriptor;
      for (auto& word : descriptor) word = random();
      f.descriptors.push_back(descriptor);
      keyframe->feature_vector[static_cast<NodeId>(random() % 100)].push_back(i);
    }
    f.grid = FeatureGrid(f.undistorted, f.Levels(), bounds);
    std::vector<WordId> words;
    for (int i = 0; i < features; ++i) words.push_back(static_cast<WordId>(random() % 100000));
    std::sort(words.begin(), words.end());
    words.erase(std::unique(words.begin(), words.end()), words.end());
    for (const WordId word : words) keyframe->bow.entries.emplace_back(word, 1.0 / words.size());
    keyframe->points.assign(static_cast<std::size_t>(features), nullptr);
    map->Add(keyframe);
    for (int i = 0; i < features; i += 3) {
      const MapPointPtr& point = points[static_cast<std::size_t>(random() % points.size())];
      if (point->observations.count(keyframe->id) > 0 || point->observations.size() >= 3) continue;
      if (point->observations.empty()) {
        point->reference = point->first_keyframe = keyframe->id;
      }
      map->AddObservation(keyframe, i, point);
    }
    if (previous) {
      const int weight = 15 + static_cast<int>(random() % 50);
      keyframe->covisible[previous->id] = weight;
      previous->covisible[keyframe->id] = weight;
      keyframe->ordered_covisible.push_back(previous->id);
      previous->ordered_covisible.push_back(keyframe->id);
      keyframe->parent = previous->id;
      keyframe->has_parent = true;
      previous->children.insert(keyframe->id);
    }
    if (k % 37 == 36) {
      const KeyFrameId other = static_cast<KeyFrameId>(random() % keyframe->id);
      keyframe->loop_edges.insert(other);
      map->GetKeyFrame(other)->loop_edges.insert(keyframe->id);
    }
    if (k % 50 == 49) {
      keyframe->bad = true;
      keyframe->T_c_parent = keyframe->T_cw * previous->T_cw.Inverse();
    }
    previous = keyframe;
  }
  // Points no keyframe saw would not be in a real map.
  for (const MapPointPtr& point : points) {
    if (point->observations.empty()) map->ErasePoint(point);
  }
}

}  // namespace ocg::testing
