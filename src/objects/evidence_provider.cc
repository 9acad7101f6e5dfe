#include "ocg/objects/evidence_provider.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>

#include "ocg/ocg/judgement_terms.h"

namespace ocg {

// The sources of src/objects/evidence/*.cc: the build writes one OCG_EVIDENCE(NAME) line
// per file into evidence_sources.inc (src/objects/CMakeLists.txt).
#define OCG_EVIDENCE(NAME) void OcgEvidenceSource_##NAME(std::vector<EvidenceSource>& sources);
#include "evidence_sources.inc"
#undef OCG_EVIDENCE

void DetectionEvidence::Fill(const KeyframeEvidence& keyframe, KeyframeObservation* observation) {
  for (const auto& [id, frame] : keyframe.detected) {
    if (frame >= keyframe.session_first_frame && keyframe.objects.count(id) > 0)
      observation->observed.push_back(id);
  }
}

void GeometryEvidence::Fill(const KeyframeEvidence& keyframe, KeyframeObservation* observation) {
  for (const auto& [id, changed] : keyframe.geometry_changed) {
    const auto it = keyframe.objects.find(id);
    if (it == keyframe.objects.end() || !it->second.has_cuboid) continue;
    ObjectGeometryUpdate& update = observation->updates[id];
    update.centroid = it->second.cuboid.centre;
    update.size = WorldExtent(it->second.cuboid, keyframe.map.R_wg);
    update.class_id = it->second.class_id;
  }
}

namespace {

// The place of a provider's field in the observation's field list; "updates" (the
// per-object values, VisitObjectUpdateFields) after them all.
std::size_t FieldPlace(const std::string& field) {
  std::size_t place = 0;
  std::size_t found = 0;
  bool listed = false;
  const KeyframeObservation observation;
  VisitObservationFields(
      [&](const ObservationField& listed_field, const auto&) {
        if (field == listed_field.name) {
          found = place;
          listed = true;
        }
        ++place;
      },
      observation);
  if (field == "updates") return place;
  if (!listed)
    throw std::logic_error("evidence provider of \"" + field +
                           "\": no such field in VisitObservationFields (observation.h)");
  return found;
}

// The index of the judgement term named mode.
std::size_t TermIndex(const char* mode) {
  const std::vector<JudgementTerm>& terms = JudgementTerms();
  for (std::size_t i = 0; i < terms.size(); ++i) {
    if (std::strcmp(terms[i].name, mode) == 0) return i;
  }
  throw std::logic_error(std::string("evidence source of mode \"") + mode +
                         "\": no such judgement term (use one of " + JudgementTermNames() + ")");
}

std::vector<EvidenceSource> MakeSources() {
  std::vector<EvidenceSource> sources;
  sources.push_back(
      {nullptr,
       [] { return std::unique_ptr<EvidenceProvider>(std::make_unique<DetectionEvidence>()); }});
  sources.push_back(
      {nullptr,
       [] { return std::unique_ptr<EvidenceProvider>(std::make_unique<GeometryEvidence>()); }});
#define OCG_EVIDENCE(NAME) OcgEvidenceSource_##NAME(sources);
#include "evidence_sources.inc"
#undef OCG_EVIDENCE
  std::vector<std::pair<std::size_t, EvidenceSource>> placed;
  for (const EvidenceSource& source : sources) {
    if (source.mode != nullptr) TermIndex(source.mode);
    const std::string field = source.make()->Field();
    const std::size_t place = FieldPlace(field);
    for (const auto& entry : placed) {
      if (entry.first == place)
        throw std::logic_error("two evidence providers fill \"" + field + "\"");
    }
    placed.emplace_back(place, source);
  }
  std::sort(placed.begin(), placed.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  sources.clear();
  for (const auto& entry : placed) sources.push_back(entry.second);
  return sources;
}

}  // namespace

const std::vector<EvidenceSource>& EvidenceSources() {
  static const std::vector<EvidenceSource> sources = MakeSources();
  return sources;
}

std::vector<std::unique_ptr<EvidenceProvider>> EvidenceProvidersFor(const OcgModes& modes) {
  std::vector<std::unique_ptr<EvidenceProvider>> providers;
  for (const EvidenceSource& source : EvidenceSources()) {
    if (source.mode == nullptr || modes.has(TermIndex(source.mode)))
      providers.push_back(source.make());
  }
  return providers;
}

}  // namespace ocg
