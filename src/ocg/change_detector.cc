#include "ocg/ocg/change_detector.h"

#include <algorithm>
#include <any>
#include <functional>
#include <iomanip>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "ocg/core/options.h"
#include "ocg/ocg/judgement_terms.h"
#include "ocg/ocg/observability.h"

namespace ocg {
namespace {

bool IsActive(ObjectState state) {
  return state == ObjectState::kObserved || state == ObjectState::kRecentlyObserved ||
         state == ObjectState::kSuspicious;
}

nlohmann::json VectorJson(const std::optional<Eigen::Vector3d>& vector) {
  if (!vector) return nullptr;
  return {vector->x(), vector->y(), vector->z()};
}

std::optional<Eigen::Vector3d> VectorFromJson(const nlohmann::json& json) {
  if (json.is_null()) return std::nullopt;
  const auto values = json.get<std::vector<double>>();
  if (values.size() != 3) throw std::invalid_argument("expected 3 numbers");
  return Eigen::Vector3d(values[0], values[1], values[2]);
}

// Later fields win, empty ones keep the earlier value (as ApplyUpdate does on a record).
void MergeUpdate(ObjectGeometryUpdate& into, const ObjectGeometryUpdate& update) {
  if (update.centroid) into.centroid = update.centroid;
  if (update.size) into.size = update.size;
  if (update.class_id) into.class_id = update.class_id;
}

nlohmann::json OptionsJson(const OcgOptions& options) {
  nlohmann::json json = nlohmann::json::object();
  VisitOcgOptionFields(options,
                       [&json](const char* name, const auto& member) { json[name] = member; });
  return json;
}

}  // namespace

class ObjectChangeDetector::KeyframeView : public GraphView {
 public:
  // observed: this keyframe's detected objects, sorted.
  KeyframeView(const ObjectChangeDetector& detector, const std::vector<ObjectId>& observed)
      : detector_(detector), observed_(observed) {}
  const std::vector<CovisibilityEdge>& Neighbours(ObjectId id) const override {
    return detector_.graph_.Neighbours(id);
  }
  const ObjectGeometry& Geometry(ObjectId id) const override {
    return detector_.records_.at(id).geometry;
  }
  bool Detected(ObjectId id) const override {
    return std::binary_search(observed_.begin(), observed_.end(), id);
  }
  void ForEachObject(
      const std::function<void(ObjectId, const ObjectGeometry&)>& visit) const override {
    for (const auto& [id, record] : detector_.records_) visit(id, record.geometry);
  }
  const OcgModes& modes() const override { return detector_.modes_; }
  std::any& KeyframeMemo(const char* key) const override {
    for (auto& [name, value] : memo_) {
      if (name == key) return value;
    }
    return memo_.emplace_back(key, std::any()).second;
  }

 private:
  const ObjectChangeDetector& detector_;
  const std::vector<ObjectId>& observed_;
  mutable std::vector<std::pair<std::string, std::any>> memo_;
};

ObjectChangeDetector::ObjectChangeDetector(OcgOptions options)
    : options_(std::move(options)), modes_(options_.modes()) {
  options_.Check();
}

void ObjectChangeDetector::ApplyUpdate(Record& record, const ObjectGeometryUpdate& update) {
  if (update.centroid) record.geometry.centroid = update.centroid;
  if (update.size) record.geometry.size = update.size;
  if (update.class_id) record.class_id = *update.class_id;
}

void ObjectChangeDetector::SetState(ObjectId id, Record& record, const StateAndDoubt& next) {
  if (next.state == ObjectState::kSuspicious && record.state.state != ObjectState::kSuspicious)
    record.suspected_in_session = true;
  record.state = next;
  if (IsActive(next.state)) {
    active_.insert(id);
  } else {
    active_.erase(id);
  }
}

void ObjectChangeDetector::UpdateIsolation(ObjectId id) {
  if (graph_.Degree(id) == 0) {
    isolated_.insert(id);
  } else {
    isolated_.erase(id);
  }
}

KeyframeResult ObjectChangeDetector::Process(const KeyframeObservation& observation) {
  const std::int64_t keyframe = observation.keyframe_id;
  last_keyframe_ = keyframe;
  last_timestamp_ = observation.timestamp;
  any_keyframe_ = true;
  std::vector<ObjectId> observed = observation.observed;
  std::sort(observed.begin(), observed.end());
  observed.erase(std::unique(observed.begin(), observed.end()), observed.end());

  for (ObjectId id : observation.forgotten) Forget(id);
  for (ObjectId id : observation.restored) Restore(id);
  // 1. Graph update, with new objects entering in state 1.
  for (ObjectId id : observed) {
    auto [it, created] = records_.try_emplace(id);
    if (!created) continue;
    it->second.first_keyframe = keyframe;
    const auto pending = pending_.find(id);
    if (pending != pending_.end()) {
      ApplyUpdate(it->second, pending->second);
      pending_.erase(pending);
    }
  }
  graph_.AddCovisibility(observed);
  for (const auto& [id, update] : observation.updates) {
    const auto it = records_.find(id);
    if (it != records_.end()) {
      ApplyUpdate(it->second, update);
    } else {
      MergeUpdate(pending_[id], update);
    }
  }
  const Eigen::Vector3d camera_centre = observation.T_cw.Inverse().translation();
  for (ObjectId id : observed) {
    Record& record = records_.at(id);
    ++record.observations;
    record.last_observed_keyframe = keyframe;
    record.observed_in_session = true;
    RecordDetectedView(record.geometry, camera_centre, options_, modes_.detected_view);
    UpdateIsolation(id);
  }

  // 2. Numerators of Eq. (1), touching only the neighbours of observed objects: every
  // (neighbour, weight) pair in one reused buffer, sorted, then summed per neighbour.
  touched_.clear();
  for (ObjectId id : observed) {
    for (const CovisibilityEdge& edge : graph_.Neighbours(id)) touched_.push_back(edge);
  }
  std::sort(touched_.begin(), touched_.end(),
            [](const CovisibilityEdge& a, const CovisibilityEdge& b) {
              return a.neighbour < b.neighbour;
            });
  observed_weight_.clear();  // (neighbour, summed weight, observed neighbours), by neighbour
  for (const CovisibilityEdge& edge : touched_) {
    if (observed_weight_.empty() || observed_weight_.back().id != edge.neighbour) {
      observed_weight_.push_back({edge.neighbour, 0, 0});
    }
    observed_weight_.back().weight += edge.weight;
    observed_weight_.back().neighbours += 1;
  }

  // Objects whose state can change: observed ones, states 1, 2, 4, state-3 objects with
  // an observed neighbour (others have rate 0 and stay), and in "fallback" mode the
  // neighbourless ones.
  candidates_.assign(observed.begin(), observed.end());
  // Objects a term's evidence names ("points": seen by their map points), if in the graph.
  const std::vector<JudgementTerm>& terms = JudgementTerms();
  for (std::size_t i = 0; i < terms.size(); ++i) {
    if (!terms[i].candidates || !modes_.has(i)) continue;
    std::vector<ObjectId> named;
    terms[i].candidates(observation, named);
    for (ObjectId id : named) {
      if (records_.count(id) > 0) candidates_.push_back(id);
    }
  }
  candidates_.insert(candidates_.end(), active_.begin(), active_.end());
  for (const ObservedWeight& entry : observed_weight_) candidates_.push_back(entry.id);
  if (modes_.isolated_fallback) {
    candidates_.insert(candidates_.end(), isolated_.begin(), isolated_.end());
  }
  if (modes_.strategy == ChangeStrategy::kVisibility) {
    // The naive baseline looks at every object: O(map size) by design.
    for (const auto& entry : records_) candidates_.push_back(entry.first);
  }
  std::sort(candidates_.begin(), candidates_.end());
  candidates_.erase(std::unique(candidates_.begin(), candidates_.end()), candidates_.end());

  const KeyframeView view(*this, observed);
  std::vector<ObjectId> outliers;
  auto weight = observed_weight_.begin();  // both lists ascend by id: walk them together
  for (ObjectId id : candidates_) {
    Record& record = records_.at(id);
    ObjectEvidence evidence;
    evidence.observed = std::binary_search(observed.begin(), observed.end(), id);
    while (weight != observed_weight_.end() && weight->id < id) ++weight;
    if (weight != observed_weight_.end() && weight->id == id) {
      evidence.observed_weight = weight->weight;
      evidence.observed_neighbours = weight->neighbours;
    }
    evidence.total_weight = graph_.WeightSum(id);
    evidence.degree = graph_.Degree(id);
    const Judgement judgement =
        JudgeObject(record.state, evidence, record.geometry, observation.T_cw, observation.camera,
                    options_, modes_, &observation, id, &view);
    record.rate = judgement.rate;
    record.rate_keyframe = keyframe;
    record.judged_by_geometry = judgement.judged_by_geometry;
    SetState(id, record, judgement.next);
    if (judgement.missed) ++record.geometry.missed_keyframes;
    if (judgement.next.state == ObjectState::kOutlier) outliers.push_back(id);
  }

  // 3. Removals last, so they did not change any rate above.
  KeyframeResult result;
  result.keyframe_id = keyframe;
  for (ObjectId id : outliers) {
    result.removed.push_back(MakeRemoval(id, keyframe, observation.timestamp));
    KeepGeometryForReentry(id);
    RemoveObject(id, modes_.restore);
  }
  return result;
}

void ObjectChangeDetector::KeepGeometryForReentry(ObjectId id) {
  // SPEC 3.1: an id observed again after its removal re-enters with its last centroid. A
  // feeding system sends a centroid only when it is new or changed, so without it an
  // object falsely removed and seen again at its old place could never be judged again.
  const Record& record = records_.at(id);
  ObjectGeometryUpdate& kept = pending_[id];
  kept.centroid = record.geometry.centroid;
  kept.size = record.geometry.size;
  if (record.class_id >= 0) kept.class_id = record.class_id;
}

RemovalEvent ObjectChangeDetector::MakeRemoval(ObjectId id, std::int64_t keyframe,
                                               double timestamp) const {
  const Record& record = records_.at(id);
  RemovalEvent event;
  event.keyframe_id = keyframe;
  event.timestamp = timestamp;
  event.object_id = id;
  event.class_id = record.class_id;
  event.centroid = record.geometry.centroid;
  event.doubt = record.state.doubt;
  return event;
}

void ObjectChangeDetector::StartSession() {
  for (auto& entry : records_) {
    entry.second.observed_in_session = false;
    entry.second.suspected_in_session = false;
  }
}

KeyframeResult ObjectChangeDetector::EndSession(const SuccessorCheck& may_have_become) {
  KeyframeResult result;
  result.keyframe_id = last_keyframe_;
  if (modes_.strategy != ChangeStrategy::kGraph) return result;
  // "successor": objects of each class by the keyframe they entered, to find one that
  // entered after a suspicious object was last observed (few objects: a linear pass).
  std::unordered_map<int, std::vector<std::pair<std::int64_t, ObjectId>>> entered_by_class;
  if (modes_.successor) {
    for (const auto& [id, record] : records_) {
      if (record.class_id >= 0)
        entered_by_class[record.class_id].push_back({record.first_keyframe, id});
    }
  }
  const auto successor = [&](ObjectId id, const Record& record) -> std::optional<ObjectId> {
    const auto it = entered_by_class.find(record.class_id);
    if (it == entered_by_class.end()) return std::nullopt;
    std::optional<ObjectId> found;
    for (const auto& [entered, other] : it->second) {
      if (other == id || entered <= record.last_observed_keyframe ||
          graph_.EdgeWeight(id, other) > 0)
        continue;
      // A successor in doubt itself explains nothing.
      const StateAndDoubt& its = records_.at(other).state;
      if (its.state == ObjectState::kSuspicious && its.doubt > options_.tau_doubt) continue;
      // Among its neighbours: carried within the region it was seen in, not a new region's
      // object of its class first seen after it.
      bool shares_neighbour = false;
      for (const CovisibilityEdge& edge : graph_.Neighbours(other)) {
        if (edge.neighbour != id && graph_.EdgeWeight(id, edge.neighbour) > 0) {
          shares_neighbour = true;
          break;
        }
      }
      if (!shares_neighbour) continue;
      if (may_have_become && !may_have_become(id, other)) continue;
      if (!found || other < *found) found = other;
    }
    return found;
  };
  std::vector<std::pair<ObjectId, std::optional<ObjectId>>> outliers;
  for (const auto& [id, record] : records_) {
    if (!record.suspected_in_session || record.state.state != ObjectState::kSuspicious ||
        record.state.doubt <= options_.tau_doubt)
      continue;
    if (!record.observed_in_session) {
      outliers.push_back({id, std::nullopt});
    } else if (const std::optional<ObjectId> next = successor(id, record)) {
      outliers.push_back({id, next});
    }
  }
  std::sort(outliers.begin(), outliers.end());
  for (const auto& [id, next] : outliers) {
    RemovalEvent event = MakeRemoval(id, last_keyframe_, last_timestamp_);
    // What happened, in the detector's terms: the generic "outlier" reads as a removal on
    // leaving a region the camera never left.
    std::ostringstream reason;
    reason << std::fixed << std::setprecision(1);
    if (next) {
      reason << "session ended: suspicious, doubt " << event.doubt << " > tau_doubt "
             << options_.tau_doubt << ", and object " << *next
             << " of its class, never seen with it, entered after its last observation";
    } else {
      reason << "session ended: not observed in this session while its neighbours were "
                "(suspicious), doubt "
             << event.doubt << " > tau_doubt " << options_.tau_doubt;
    }
    event.reason = reason.str();
    result.removed.push_back(event);
    KeepGeometryForReentry(id);
    RemoveObject(id);
  }
  return result;
}

void ObjectChangeDetector::RemoveObject(ObjectId id, bool archive) {
  std::vector<ObjectId> neighbours;
  for (const CovisibilityEdge& edge : graph_.Neighbours(id)) neighbours.push_back(edge.neighbour);
  if (archive) removed_[id] = {records_.at(id), graph_.Neighbours(id)};
  graph_.RemoveNode(id);
  records_.erase(id);
  active_.erase(id);
  isolated_.erase(id);
  for (ObjectId neighbour : neighbours) UpdateIsolation(neighbour);
}

bool ObjectChangeDetector::Forget(ObjectId id) {
  pending_.erase(id);
  removed_.erase(id);
  if (records_.count(id) == 0) return false;
  RemoveObject(id);
  return true;
}

bool ObjectChangeDetector::Restore(ObjectId id) {
  const auto it = removed_.find(id);
  if (it == removed_.end() || records_.count(id) > 0) return false;
  Record& record = records_.emplace(id, it->second.record).first->second;
  graph_.AddNode(id);
  // The co-visibility it had is still true of the scene: the objects it was seen with are
  // where they were, so its neighbours judge it as before the removal.
  for (const CovisibilityEdge& edge : it->second.edges) {
    if (!graph_.Contains(edge.neighbour)) continue;
    graph_.SetEdge(id, edge.neighbour, edge.weight);
    UpdateIsolation(edge.neighbour);
  }
  removed_.erase(it);
  // Its kept geometry, or a newer one sent while it was out of the graph.
  const auto pending = pending_.find(id);
  if (pending != pending_.end()) {
    ApplyUpdate(record, pending->second);
    pending_.erase(pending);
  }
  record.rate = 0.0;
  record.rate_keyframe = -1;
  record.judged_by_geometry = false;
  SetState(id, record, {ObjectState::kObserved, 0.0});
  UpdateIsolation(id);
  return true;
}

ObjectStatus ObjectChangeDetector::MakeStatus(ObjectId id, const Record& record) const {
  ObjectStatus status;
  status.id = id;
  status.state = record.state.state;
  status.doubt = record.state.doubt;
  const bool current = any_keyframe_ && record.rate_keyframe == last_keyframe_;
  // Objects not visited at this keyframe had no observed neighbour: their rate is 0.
  status.active_edge_rate = current ? record.rate : 0.0;
  status.judged_by_geometry = current && record.judged_by_geometry;
  status.class_id = record.class_id;
  status.geometry = record.geometry;
  status.observations = record.observations;
  status.first_keyframe = record.first_keyframe;
  status.last_observed_keyframe = record.last_observed_keyframe;
  return status;
}

std::optional<ObjectStatus> ObjectChangeDetector::Status(ObjectId id) const {
  const auto it = records_.find(id);
  if (it == records_.end()) return std::nullopt;
  return MakeStatus(id, it->second);
}

std::optional<ObjectGeometryUpdate> ObjectChangeDetector::PendingGeometry(ObjectId id) const {
  const auto it = pending_.find(id);
  if (it == pending_.end()) return std::nullopt;
  return it->second;
}

std::vector<ObjectStatus> ObjectChangeDetector::Snapshot() const {
  std::vector<ObjectStatus> statuses;
  statuses.reserve(records_.size());
  for (ObjectId id : graph_.NodeIds()) statuses.push_back(MakeStatus(id, records_.at(id)));
  return statuses;
}

std::string ObjectChangeDetector::ToJson() const {
  nlohmann::json nodes = nlohmann::json::array();
  nlohmann::json edges = nlohmann::json::array();
  for (const ObjectStatus& status : Snapshot()) {
    nodes.push_back({{"id", status.id},
                     {"state", static_cast<int>(status.state)},
                     {"doubt", status.doubt},
                     {"active_edge_rate", status.active_edge_rate},
                     {"class_id", status.class_id},
                     {"centroid", VectorJson(status.geometry.centroid)},
                     {"size", VectorJson(status.geometry.size)},
                     {"max_observed_distance", status.geometry.max_observed_distance},
                     {"observations", status.observations},
                     {"first_keyframe", status.first_keyframe},
                     {"last_observed_keyframe", status.last_observed_keyframe}});
    if (!status.geometry.view_directions.empty()) {  // "view" mode only
      nlohmann::json directions = nlohmann::json::array();
      for (const Eigen::Vector3d& direction : status.geometry.view_directions)
        directions.push_back(VectorJson(direction));
      nodes.back()["view_directions"] = directions;
    }
    if (modes_.detection_reliability) {
      nodes.back()["detection_record"] = {status.geometry.detected_keyframes,
                                          status.geometry.missed_keyframes};
    }
    for (const CovisibilityEdge& edge : graph_.Neighbours(status.id)) {
      if (edge.neighbour > status.id) edges.push_back({status.id, edge.neighbour, edge.weight});
    }
  }
  // Sorted by id, so equal detectors write equal files.
  std::map<ObjectId, const ObjectGeometryUpdate*> pending_by_id;
  for (const auto& [id, update] : pending_) pending_by_id[id] = &update;
  nlohmann::json pending = nlohmann::json::array();
  for (const auto& [id, update] : pending_by_id) {
    pending.push_back({{"id", id},
                       {"class_id", update->class_id ? nlohmann::json(*update->class_id)
                                                     : nlohmann::json(nullptr)},
                       {"centroid", VectorJson(update->centroid)},
                       {"size", VectorJson(update->size)}});
  }
  const nlohmann::json root = {
      {"format", "ocg-graph"},
      {"version", 1},
      {"keyframe", any_keyframe_ ? nlohmann::json(last_keyframe_) : nlohmann::json(nullptr)},
      {"options", OptionsJson(options_)},
      {"nodes", nodes},
      {"edges", edges},
      {"pending", pending}};
  return root.dump(1) + "\n";
}

ObjectChangeDetector ObjectChangeDetector::FromJson(const std::string& text) {
  try {
    const nlohmann::json root = nlohmann::json::parse(text);
    if (root.value("format", "") != "ocg-graph") {
      throw std::invalid_argument("not an OCG graph file (\"format\" is not \"ocg-graph\")");
    }
    const nlohmann::json& json_options = root.at("options");
    OcgOptions options;
    VisitOcgOptionFields(options, [&json_options](const char* name, auto& member) {
      // Files written before a field existed keep its default.
      if (json_options.contains(name)) json_options.at(name).get_to(member);
    });
    ObjectChangeDetector detector(options);
    if (!root.at("keyframe").is_null()) {
      detector.last_keyframe_ = root.at("keyframe").get<std::int64_t>();
      detector.any_keyframe_ = true;
    }
    for (const nlohmann::json& node : root.at("nodes")) {
      const ObjectId id = node.at("id").get<ObjectId>();
      const int state = node.at("state").get<int>();
      if (state < 1 || state > 4) {
        throw std::invalid_argument("node " + std::to_string(id) + ": state must be 1 to 4");
      }
      if (!detector.graph_.AddNode(id)) {
        throw std::invalid_argument("node " + std::to_string(id) + " listed twice");
      }
      Record& record = detector.records_[id];
      record.class_id = node.at("class_id").get<int>();
      record.geometry.centroid = VectorFromJson(node.at("centroid"));
      record.geometry.size = VectorFromJson(node.at("size"));
      record.geometry.max_observed_distance = node.at("max_observed_distance").get<double>();
      if (node.contains("view_directions")) {
        for (const nlohmann::json& direction : node.at("view_directions"))
          record.geometry.view_directions.push_back(*VectorFromJson(direction));
      }
      if (node.contains("detection_record")) {  // "reliability" mode only
        record.geometry.detected_keyframes = node.at("detection_record").at(0).get<std::uint32_t>();
        record.geometry.missed_keyframes = node.at("detection_record").at(1).get<std::uint32_t>();
      }
      record.observations = node.at("observations").get<std::uint32_t>();
      record.first_keyframe = node.at("first_keyframe").get<std::int64_t>();
      record.last_observed_keyframe = node.at("last_observed_keyframe").get<std::int64_t>();
      record.rate = node.at("active_edge_rate").get<double>();
      record.rate_keyframe = detector.last_keyframe_;
      detector.SetState(id, record,
                        {static_cast<ObjectState>(state), node.at("doubt").get<double>()});
    }
    for (const nlohmann::json& edge : root.at("edges")) {
      const auto a = edge.at(0).get<ObjectId>();
      const auto b = edge.at(1).get<ObjectId>();
      if (!detector.graph_.Contains(a) || !detector.graph_.Contains(b)) {
        throw std::invalid_argument("edge " + std::to_string(a) + "-" + std::to_string(b) +
                                    " names an unknown node");
      }
      detector.graph_.SetEdge(a, b, edge.at(2).get<std::uint32_t>());
    }
    if (root.contains("pending")) {  // files written before it existed have none
      for (const nlohmann::json& entry : root.at("pending")) {
        ObjectGeometryUpdate& update = detector.pending_[entry.at("id").get<ObjectId>()];
        if (!entry.at("class_id").is_null()) update.class_id = entry.at("class_id").get<int>();
        update.centroid = VectorFromJson(entry.at("centroid"));
        update.size = VectorFromJson(entry.at("size"));
      }
    }
    for (const auto& entry : detector.records_) detector.UpdateIsolation(entry.first);
    return detector;
  } catch (const nlohmann::json::exception& error) {
    throw std::invalid_argument(std::string("OCG graph JSON: ") + error.what());
  } catch (const OptionError& error) {
    throw std::invalid_argument(std::string("OCG graph JSON options: ") + error.what());
  }
}

}  // namespace ocg
