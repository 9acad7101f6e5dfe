#include "ocg/eval/object_metrics.h"

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "ocg/core/file_io.h"
#include "ocg/eval/trajectory_error.h"
#include "ocg/io/change_entries.h"
#include "ocg/io/text_lines.h"
#include "ocg/io/trajectory.h"

namespace ocg {
namespace {

nlohmann::json ParseJsonFile(const std::string& path) {
  const std::string text = ReadTextFile(path);
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& error) {
    throw ParseError(path + ": not valid JSON: " + error.what());
  }
}

Eigen::Vector3d Vector3(const nlohmann::json& json, const std::string& what) {
  const auto values = json.get<std::vector<double>>();
  if (values.size() != 3) throw std::invalid_argument(what + " needs 3 numbers");
  return {values[0], values[1], values[2]};
}

// A placement's "frames_in_view": a count, or -1 when the file has none (older files:
// taken as in view). Every placement's is checked.
long long FramesInView(const nlohmann::json& placement, int object_id) {
  const auto found = placement.find("frames_in_view");
  if (found == placement.end()) return -1;
  if (!found->is_number_integer() || found->get<long long>() < 0) {
    throw std::invalid_argument("object " + std::to_string(object_id) +
                                ": frames_in_view must be a non-negative integer, not " +
                                found->dump());
  }
  return found->get<long long>();
}

bool Near(const GroundTruthPlace& place, int class_id, const Eigen::Vector3d& centre) {
  return place.class_id == class_id && (place.centre - centre).norm() < place.radius;
}

bool Near(const GroundTruthPlace& place, const RunObject& object) {
  return Near(place, object.class_id, object.centre);
}

}  // namespace

ObjectGroundTruth ReadObjectGroundTruth(const std::string& path,
                                        const ObjectMatchOptions& options) {
  const nlohmann::json root = ParseJsonFile(path);
  ObjectGroundTruth truth;
  try {
    for (const nlohmann::json& object : root.at("objects")) {
      GroundTruthPlace place;
      place.object_id = object.at("id").get<int>();
      place.class_id = object.at("class_id").get<int>();
      const Eigen::Vector3d size = Vector3(object.at("size"), "size");
      place.radius = std::max(options.distance_factor * size.maxCoeff(), options.min_distance);
      std::vector<Eigen::Vector3d> present;
      bool present_at_end = false;
      bool last_in_view = true;
      for (const nlohmann::json& placement : object.at("history")) {
        present_at_end = placement.at("present").get<bool>();
        const long long frames_in_view = FramesInView(placement, place.object_id);
        if (!present_at_end) continue;
        present.push_back(Vector3(placement.at("centre"), "centre"));
        last_in_view = frames_in_view != 0;
      }
      for (std::size_t i = 0; i < present.size(); ++i) {
        place.centre = present[i];
        if (present_at_end && i + 1 == present.size()) {
          if (last_in_view || options.include_never_in_view) {
            truth.static_places.push_back(place);
          } else {
            truth.never_in_view_places.push_back(place);
          }
        } else {
          truth.outdated_places.push_back(place);
        }
      }
    }
  } catch (const std::exception& error) {
    throw ParseError(path + ": " + error.what() +
                     " (expected {\"objects\": [{\"id\", \"class_id\", \"size\", \"history\": "
                     "[{\"present\", \"centre\", \"frames_in_view\" (optional)}]}]})");
  }
  return truth;
}

std::vector<RunObject> ReadRunObjects(const std::string& run_dir) {
  std::vector<RunObject> objects;
  const std::string objects_path = run_dir + "/objects.json";
  const nlohmann::json live = ParseJsonFile(objects_path);
  try {
    for (const nlohmann::json& entry : live.at("objects")) {
      objects.push_back({entry.at("id").get<long long>(), entry.at("class_id").get<int>(),
                         Vector3(entry.at("cuboid").at("centre"), "centre"), true, std::nullopt});
    }
  } catch (const std::exception& error) {
    throw ParseError(objects_path + ": " + error.what());
  }
  const std::string changes_path = run_dir + "/changes.json";
  if (!std::filesystem::exists(changes_path)) return objects;
  const nlohmann::json changes = ParseJsonFile(changes_path);
  try {
    const nlohmann::json& list = changes.at("changes");
    const std::vector<bool> standing = StandingRemovals(list);
    for (std::size_t i = 0; i < list.size(); ++i) {
      // A move's entry holds the object removed from its old place ("centroid"); a removal
      // undone by a restore is not a removed object (the object is live).
      const nlohmann::json& change = list[i];
      const std::string type = change.at("type").get<std::string>();
      if (!standing[i] || change.at("centroid").is_null()) continue;
      RunObject object{change.at("object_id").get<long long>(), change.at("class_id").get<int>(),
                       Vector3(change.at("centroid"), "centroid"), false, std::nullopt};
      if (type == "moved") {
        object.moved_to = Vector3(change.at("to").at("cuboid").at("centre"), "to.cuboid.centre");
      }
      objects.push_back(object);
    }
  } catch (const std::exception& error) {
    throw ParseError(changes_path + ": " + error.what());
  }
  return objects;
}

void ComputeRatios(ObjectMetrics* m) {
  const auto ratio = [](int numerator, int denominator) {
    return denominator > 0 ? static_cast<double>(numerator) / denominator : 0.0;
  };
  m->acc = ratio(m->corr_s, m->corr_s + m->unident_s + m->redun_s + m->delet_s + m->unident_m);
  m->prec = ratio(m->corr_s, m->corr_s + m->redun_s + m->unident_m);
  m->recall = ratio(m->corr_s, m->corr_s + m->unident_s + m->delet_s);
}

ObjectMetrics ComputeObjectMetrics(const ObjectGroundTruth& truth,
                                   const std::vector<RunObject>& objects) {
  ObjectMetrics metrics;
  metrics.gt_static = static_cast<int>(truth.static_places.size());
  metrics.gt_outdated = static_cast<int>(truth.outdated_places.size());
  metrics.gt_never_in_view = static_cast<int>(truth.never_in_view_places.size());
  for (const GroundTruthPlace& place : truth.never_in_view_places) {
    metrics.never_in_view_ids.push_back(place.object_id);
  }
  std::vector<std::size_t> live;
  for (std::size_t i = 0; i < objects.size(); ++i) {
    if (objects[i].live) {
      live.push_back(i);
      ++metrics.live_objects;
    } else {
      ++metrics.removed_objects;
    }
  }

  // One-to-one, greedy by distance: each static place takes its nearest live object first.
  struct Pair {
    double distance;
    std::size_t place, object;
  };
  std::vector<Pair> pairs;
  for (std::size_t p = 0; p < truth.static_places.size(); ++p) {
    for (std::size_t o : live) {
      if (Near(truth.static_places[p], objects[o])) {
        pairs.push_back({(truth.static_places[p].centre - objects[o].centre).norm(), p, o});
      }
    }
  }
  std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) {
    return a.distance != b.distance ? a.distance < b.distance
                                    : std::tie(a.place, a.object) < std::tie(b.place, b.object);
  });
  std::vector<bool> place_matched(truth.static_places.size(), false);
  std::vector<bool> object_matched(objects.size(), false);
  for (const Pair& pair : pairs) {
    if (place_matched[pair.place] || object_matched[pair.object]) continue;
    place_matched[pair.place] = object_matched[pair.object] = true;
  }

  for (std::size_t p = 0; p < truth.static_places.size(); ++p) {
    const GroundTruthPlace& place = truth.static_places[p];
    if (place_matched[p]) {
      ++metrics.corr_s;
      continue;
    }
    const bool ever = std::any_of(objects.begin(), objects.end(),
                                  [&](const RunObject& object) { return Near(place, object); });
    if (ever) {
      ++metrics.delet_s;
      metrics.deleted_static_ids.push_back(place.object_id);
    } else {
      ++metrics.unident_s;
      metrics.unidentified_static_ids.push_back(place.object_id);
    }
  }
  for (const GroundTruthPlace& place : truth.outdated_places) {
    bool ever = false, now = false;
    for (const RunObject& object : objects) {
      if (!Near(place, object)) continue;
      ever = true;
      now = now || object.live;
    }
    if (now) {
      ++metrics.unident_m;
      metrics.unidentified_moved_ids.push_back(place.object_id);
    } else if (ever) {
      ++metrics.corr_m;
    }
  }
  for (const GroundTruthPlace& old_place : truth.outdated_places) {
    const auto now = std::find_if(
        truth.static_places.begin(), truth.static_places.end(),
        [&](const GroundTruthPlace& place) { return place.object_id == old_place.object_id; });
    if (now == truth.static_places.end()) continue;  // removed, not moved
    ++metrics.gt_moves;
    const bool reported = std::any_of(objects.begin(), objects.end(), [&](const RunObject& object) {
      return object.moved_to && Near(old_place, object) &&
             Near(*now, object.class_id, *object.moved_to);
    });
    if (reported) ++metrics.moves_right;
  }
  for (std::size_t o : live) {
    if (object_matched[o]) continue;
    const RunObject& object = objects[o];
    const auto near = [&object](const GroundTruthPlace& place) { return Near(place, object); };
    if (std::any_of(truth.outdated_places.begin(), truth.outdated_places.end(), near)) continue;
    // A place the sequence never shows is ignored, as benchmarks ignore regions no one can
    // label: an object there (carried from an earlier session, say) is neither right nor
    // redundant.
    if (std::any_of(truth.never_in_view_places.begin(), truth.never_in_view_places.end(), near)) {
      metrics.never_in_view_object_ids.push_back(object.id);
      continue;
    }
    ++metrics.redun_s;
    if (std::any_of(truth.static_places.begin(), truth.static_places.end(), near)) {
      ++metrics.redun_duplicates;
      metrics.duplicate_ids.push_back(object.id);
    } else {
      ++metrics.redun_spurious;
      metrics.spurious_ids.push_back(object.id);
    }
  }
  ComputeRatios(&metrics);
  return metrics;
}

void TransformObjects(const Sim3& world_from_run, std::vector<RunObject>* objects) {
  for (RunObject& object : *objects) {
    object.centre = world_from_run * object.centre;
    if (object.moved_to) object.moved_to = world_from_run * *object.moved_to;
  }
}

ObjectMetrics EvaluateRunObjects(const std::string& objects_gt_path, const std::string& run_dir,
                                 const std::string& groundtruth_path,
                                 const ObjectMatchOptions& options,
                                 std::optional<RunAlignment>* alignment) {
  const ObjectGroundTruth truth = ReadObjectGroundTruth(objects_gt_path, options);
  std::vector<RunObject> objects = ReadRunObjects(run_dir);
  if (alignment != nullptr) alignment->reset();
  if (!groundtruth_path.empty()) {
    // Monocular runs live in their own frame and scale: align the run's trajectory first.
    std::string trajectory = run_dir + "/KeyFrameTrajectory.txt";
    if (!std::filesystem::exists(trajectory)) trajectory = run_dir + "/CameraTrajectory.txt";
    const AteResult ate =
        ComputeAte(ReadTumTrajectory(groundtruth_path), ReadTumTrajectory(trajectory), {});
    TransformObjects(ate.reference_from_estimate, &objects);
    if (alignment != nullptr) {
      *alignment = RunAlignment{trajectory, ate.pairs.size(), ate.reference_from_estimate.scale(),
                                ate.translation.rmse};
    }
  }
  return ComputeObjectMetrics(truth, objects);
}

}  // namespace ocg
