#include "ocg/slam/map.h"

#include <algorithm>
#include <thread>

namespace ocg {

int KeyFrame::TrackedPoints(int min_observations) const {
  int count = 0;
  for (const MapPointPtr& point : points) {
    if (point && !point->bad && static_cast<int>(point->observations.size()) >= min_observations) {
      ++count;
    }
  }
  return count;
}

std::optional<PointProjection> ProjectPoint(const PinholeCamera& camera, const ImageBounds& bounds,
                                            const SE3& T_cw, const MapPoint& point,
                                            bool check_scale) {
  const Eigen::Vector3d Xc = T_cw * point.position;
  if (Xc.z() <= 0.0) return std::nullopt;
  PointProjection p;
  p.pixel = camera.ProjectUndistorted(Xc);
  if (!bounds.Contains(p.pixel)) return std::nullopt;
  const Eigen::Vector3d ray = point.position - T_cw.Inverse().translation();
  p.distance = ray.norm();
  if (check_scale) {
    if (p.distance < 0.8 * point.min_distance || p.distance > 1.2 * point.max_distance) {
      return std::nullopt;
    }
    p.view_cos = ray.dot(point.normal) / p.distance;
    if (p.view_cos < 0.5) return std::nullopt;
  }
  return p;
}

std::vector<bool> KeyFrame::GoodPointMask() const {
  std::vector<bool> mask(points.size());
  for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = points[i] && !points[i]->bad;
  return mask;
}

std::unique_lock<std::mutex> Map::LockForTracking() const {
  trackers_waiting_.fetch_add(1);
  std::unique_lock<std::mutex> lock(mutex_);
  trackers_waiting_.fetch_sub(1);
  return lock;
}

bool Map::LetWaitingTrackerIn(std::unique_lock<std::mutex>& lock,
                              std::chrono::microseconds max_wait) const {
  if (!TrackerWaiting()) return false;
  lock.unlock();
  const auto until = std::chrono::steady_clock::now() + max_wait;
  while (TrackerWaiting() && std::chrono::steady_clock::now() < until) std::this_thread::yield();
  lock.lock();
  return true;
}

KeyFramePtr Map::GetKeyFrame(KeyFrameId id) const {
  const auto it = keyframes_.find(id);
  return it == keyframes_.end() ? nullptr : it->second;
}

std::size_t Map::LiveKeyFrameCount() const {
  std::size_t count = 0;
  for (const auto& [id, keyframe] : keyframes_) count += keyframe->bad ? 0 : 1;
  return count;
}

std::size_t Map::KeyFrameCount(int map) const {
  std::size_t count = 0;
  for (const auto& [id, keyframe] : keyframes_) count += keyframe->map == map ? 1 : 0;
  return count;
}

std::size_t Map::LiveKeyFrameCount(int map) const {
  std::size_t count = 0;
  for (const auto& [id, keyframe] : keyframes_) count += !keyframe->bad && keyframe->map == map;
  return count;
}

void Map::Add(const KeyFramePtr& keyframe) {
  keyframes_[keyframe->id] = keyframe;
  const auto [first, inserted] = first_keyframes_.emplace(keyframe->map, keyframe->id);
  if (!inserted && keyframe->id < first->second) first->second = keyframe->id;
  journal_.KeyFrame(keyframe->id);
}

std::optional<KeyFrameId> Map::FirstKeyFrame(int map) const {
  const auto first = first_keyframes_.find(map);
  if (first == first_keyframes_.end()) return std::nullopt;
  return first->second;
}

std::vector<KeyFrameId> Map::EraseMap(int map) {
  std::vector<KeyFrameId> erased;
  for (auto it = keyframes_.begin(); it != keyframes_.end();) {
    if (it->second->map == map) {
      erased.push_back(it->first);
      it = keyframes_.erase(it);
    } else {
      ++it;
    }
  }
  first_keyframes_.erase(map);
  for (auto it = points_.begin(); it != points_.end();) {
    if (it->second->map == map) {
      it->second->bad = true;
      point_index_.erase(it->first);
      it = points_.erase(it);
    } else {
      ++it;
    }
  }
  journal_.Everything();
  return erased;
}

void Map::MoveMap(int from, int into, const Sim3& S_into_from) {
  const Sim3 S_from_into = S_into_from.Inverse();
  for (const auto& [id, keyframe] : keyframes_) {
    if (keyframe->map != from) continue;
    const Sim3 S_cw = Sim3(keyframe->T_cw) * S_from_into;
    keyframe->T_cw = SE3(S_cw.rotation(), S_cw.translation() / S_cw.scale());
    // A culled keyframe's pose relative to its parent (both moved alike) keeps its
    // rotation; its translation is in map units, which change by the scale.
    keyframe->T_c_parent = SE3(keyframe->T_c_parent.rotation(),
                               keyframe->T_c_parent.translation() * S_into_from.scale());
    keyframe->map = into;
  }
  for (const auto& [id, point] : points_) {
    if (point->map != from) continue;
    point->position = S_into_from * point->position;
    point->min_distance *= S_into_from.scale();
    point->max_distance *= S_into_from.scale();
    point->map = into;
  }
  const auto moved = first_keyframes_.find(from);
  if (moved != first_keyframes_.end()) {
    const auto [first, inserted] = first_keyframes_.emplace(into, moved->second);
    if (!inserted) first->second = std::min(first->second, moved->second);
    first_keyframes_.erase(from);
  }
  if (current_map_ == from) current_map_ = into;
  merged_into_[from] = {into, S_into_from.scale()};
  ++merges_;
  last_merge_scale_ = S_into_from.scale();
  journal_.Everything();
}

double Map::ScaleInto(int from, int to) const {
  double scale = 1.0;
  for (int map = from; map != to;) {
    const auto merged = merged_into_.find(map);
    if (merged == merged_into_.end()) return 1.0;
    scale *= merged->second.second;
    map = merged->second.first;
  }
  return scale;
}

void Map::Clear() {
  merged_into_.clear();
  keyframes_.clear();
  points_.clear();
  point_index_.clear();
  next_keyframe_id_ = 0;
  next_point_id_ = 0;
  current_map_ = 0;
  map_count_ = 1;
  first_keyframes_.clear();
  journal_.Everything();
}

void Map::AddObservation(const KeyFramePtr& keyframe, int feature, const MapPointPtr& point) {
  point->observations[keyframe->id] = feature;
  keyframe->points[static_cast<std::size_t>(feature)] = point;
}

void Map::EraseObservation(const KeyFramePtr& keyframe, const MapPointPtr& point) {
  const auto it = point->observations.find(keyframe->id);
  if (it == point->observations.end()) return;
  MapPointPtr& slot = keyframe->points[static_cast<std::size_t>(it->second)];
  if (slot == point) slot.reset();
  point->observations.erase(it);
  if (point->observations.size() <= 2) {
    ErasePoint(point);  // a monocular point needs at least two views to stay
  } else if (point->reference == keyframe->id) {
    point->reference = point->observations.begin()->first;
  }
}

void Map::ErasePoint(const MapPointPtr& point) {
  if (point->bad) return;
  point->bad = true;
  for (const auto& [keyframe_id, feature] : point->observations) {
    if (const KeyFramePtr keyframe = GetKeyFrame(keyframe_id)) {
      MapPointPtr& slot = keyframe->points[static_cast<std::size_t>(feature)];
      if (slot == point) slot.reset();
    }
  }
  point->observations.clear();
  points_.erase(point->id);
  point_index_.erase(point->id);
  journal_.Point(point->id);
}

void Map::ReplacePoint(const MapPointPtr& old_point, const MapPointPtr& new_point) {
  if (old_point == new_point || old_point->bad) return;
  const std::map<KeyFrameId, int> observations = old_point->observations;
  old_point->observations.clear();
  old_point->bad = true;
  for (const auto& [keyframe_id, feature] : observations) {
    const KeyFramePtr keyframe = GetKeyFrame(keyframe_id);
    if (!keyframe) continue;
    if (new_point->observations.count(keyframe_id) == 0) {
      AddObservation(keyframe, feature, new_point);
    } else {
      keyframe->points[static_cast<std::size_t>(feature)].reset();
    }
  }
  new_point->found += old_point->found;
  new_point->visible += old_point->visible;
  points_.erase(old_point->id);
  point_index_.erase(old_point->id);
  journal_.Point(old_point->id);
}

void Map::UpdatePointGeometry(const MapPointPtr& point, const ScalePyramid& pyramid) const {
  if (point->observations.empty()) return;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  for (const auto& [keyframe_id, feature] : point->observations) {
    if (const KeyFramePtr keyframe = GetKeyFrame(keyframe_id)) {
      normal += (point->position - keyframe->Centre()).normalized();
    }
  }
  if (normal.norm() > 0.0) point->normal = normal.normalized();
  const KeyFramePtr reference = GetKeyFrame(point->reference);
  if (!reference) return;
  const auto it = point->observations.find(reference->id);
  if (it == point->observations.end()) return;
  const double distance = (point->position - reference->Centre()).norm();
  const int level = reference->features.keypoints[static_cast<std::size_t>(it->second)].octave;
  point->max_distance = distance * pyramid.scale[static_cast<std::size_t>(level)];
  point->min_distance = point->max_distance / pyramid.scale.back();
}

void Map::UpdatePointDescriptor(const MapPointPtr& point) const {
  std::vector<Descriptor> descriptors;
  for (const auto& [keyframe_id, feature] : point->observations) {
    if (const KeyFramePtr keyframe = GetKeyFrame(keyframe_id)) {
      descriptors.push_back(keyframe->features.descriptors[static_cast<std::size_t>(feature)]);
    }
  }
  if (descriptors.empty()) return;
  std::size_t best = 0;
  int best_median = kDescriptorBits + 1;
  std::vector<int> distances(descriptors.size());
  for (std::size_t i = 0; i < descriptors.size(); ++i) {
    for (std::size_t j = 0; j < descriptors.size(); ++j) {
      distances[j] = HammingDistance(descriptors[i], descriptors[j]);
    }
    std::nth_element(distances.begin(), distances.begin() + static_cast<long>(distances.size() / 2),
                     distances.end());
    if (distances[distances.size() / 2] < best_median) {
      best_median = distances[distances.size() / 2];
      best = i;
    }
  }
  // Noted only when it changed: a point's descriptor is updated at each new observation,
  // and mostly stays the one it was (a reader would read it again for nothing).
  if (point->descriptor == descriptors[best]) return;
  point->descriptor = descriptors[best];
  journal_.Point(point->id);
}

void Map::UpdateConnections(const KeyFramePtr& keyframe) {
  std::map<KeyFrameId, int> shared;
  for (const MapPointPtr& point : keyframe->points) {
    if (!point || point->bad) continue;
    for (const auto& [other, feature] : point->observations) {
      if (other != keyframe->id) ++shared[other];
    }
  }
  if (shared.empty()) return;
  std::map<KeyFrameId, int> edges;
  KeyFrameId best = shared.begin()->first;
  for (const auto& [other, count] : shared) {
    if (count > shared[best]) best = other;
    if (count >= kCovisibilityThreshold) edges[other] = count;
  }
  if (edges.empty()) edges[best] = shared[best];
  auto order = [this](const KeyFramePtr& k) {
    std::vector<std::pair<int, KeyFrameId>> ranked;
    for (const auto& [other, count] : k->covisible) ranked.emplace_back(-count, other);
    std::sort(ranked.begin(), ranked.end());
    k->ordered_covisible.clear();
    for (const auto& [negative, other] : ranked) k->ordered_covisible.push_back(other);
  };
  for (const auto& [other, count] : edges) {
    if (const KeyFramePtr k = GetKeyFrame(other)) {
      k->covisible[keyframe->id] = count;
      order(k);
    }
  }
  keyframe->covisible = edges;
  order(keyframe);
  // The spanning tree grows from older to newer keyframes, so it can never close a cycle:
  // the parent is the best covisible keyframe older than this one.
  if (!keyframe->has_parent && keyframe->id != FirstKeyFrame(keyframe->map)) {
    for (const KeyFrameId candidate : keyframe->ordered_covisible) {
      if (candidate >= keyframe->id) continue;
      keyframe->parent = candidate;
      keyframe->has_parent = true;
      if (const KeyFramePtr parent = GetKeyFrame(candidate)) parent->children.insert(keyframe->id);
      break;
    }
  }
}

std::vector<KeyFramePtr> Map::BestCovisible(const KeyFramePtr& keyframe, std::size_t count) const {
  std::vector<KeyFramePtr> best;
  for (const KeyFrameId id : keyframe->ordered_covisible) {
    if (best.size() >= count) break;
    const KeyFramePtr other = GetKeyFrame(id);
    if (other && !other->bad) best.push_back(other);
  }
  return best;
}

void Map::EraseKeyFrame(const KeyFramePtr& keyframe) {
  if (keyframe->bad || keyframe->id == FirstKeyFrame(keyframe->map)) return;
  for (const auto& [other, count] : keyframe->covisible) {
    if (const KeyFramePtr k = GetKeyFrame(other)) {
      k->covisible.erase(keyframe->id);
      k->ordered_covisible.erase(
          std::remove(k->ordered_covisible.begin(), k->ordered_covisible.end(), keyframe->id),
          k->ordered_covisible.end());
    }
  }
  for (MapPointPtr point : keyframe->points) {
    if (point && !point->bad) EraseObservation(keyframe, point);
  }
  // Children go to the parent (ORB-SLAM2 picks the most covisible candidate; the parent
  // keeps the tree connected and is enough for trajectory output).
  if (const KeyFramePtr parent = GetKeyFrame(keyframe->parent)) {
    keyframe->T_c_parent = keyframe->T_cw * parent->T_cw.Inverse();
    parent->children.erase(keyframe->id);
    for (const KeyFrameId child_id : keyframe->children) {
      if (const KeyFramePtr child = GetKeyFrame(child_id)) {
        child->parent = parent->id;
        parent->children.insert(child_id);
      }
    }
  }
  keyframe->bad = true;
  keyframe->covisible.clear();
  keyframe->ordered_covisible.clear();
  // What stays of a culled keyframe is what frames placed relative to it need
  // (PoseFromReference: id, pose, parent, T_c_parent, time): its features, BoW vectors and
  // point slots, about 200 kB of 1000 features with their grid, are never read again.
  // Released, so that a long run that keeps revisiting places, and so keeps making and
  // culling keyframes there, does not grow by them.
  keyframe->features = ExtractedFeatures();
  keyframe->bow = BowVector();
  keyframe->feature_vector = FeatureVector();
  keyframe->points = std::vector<MapPointPtr>();
  journal_.KeyFrame(keyframe->id);
}

std::optional<AnchoredPose> PoseFromAnchor(const Map& map, const Anchor& anchor,
                                           KeyFrameId* live_keyframe) {
  SE3 relative = anchor.T_c_keyframe;
  KeyFramePtr keyframe = anchor.keyframe;
  while (keyframe && map.GetKeyFrame(keyframe->id) != keyframe) {
    if (!keyframe->anchor) return std::nullopt;  // erased with its map
    // Not linked yet: its pose and its anchor's relative pose were measured together, in
    // the same map and units as the relative pose on it.
    relative = relative * keyframe->anchor->T_c_keyframe;
    keyframe = keyframe->anchor->keyframe;
  }
  if (!keyframe) return std::nullopt;
  const double scale = map.ScaleInto(anchor.map, keyframe->map);
  if (scale != 1.0) relative = SE3(relative.rotation(), relative.translation() * scale);
  const std::optional<SE3> T_cw = PoseFromReference(map, keyframe->id, relative, live_keyframe);
  if (!T_cw) return std::nullopt;
  return AnchoredPose{*T_cw, keyframe->map};
}

std::optional<SE3> PoseFromReference(const Map& map, KeyFrameId reference, const SE3& T_c_reference,
                                     KeyFrameId* anchor) {
  KeyFramePtr keyframe = map.GetKeyFrame(reference);
  SE3 relative = T_c_reference;
  while (keyframe && keyframe->bad && keyframe->has_parent) {
    relative = relative * keyframe->T_c_parent;
    keyframe = map.GetKeyFrame(keyframe->parent);
  }
  if (!keyframe) return std::nullopt;
  if (anchor != nullptr) *anchor = keyframe->id;
  return relative * keyframe->T_cw;
}

}  // namespace ocg
