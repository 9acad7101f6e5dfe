#include "ocg/sim/detector.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace ocg::sim {

std::uint64_t SeedMix(std::uint64_t a, std::uint64_t b) {
  std::uint64_t x = a * 0x9e3779b97f4a7c15ULL ^ (b + 0x632be59bd9b4e019ULL + (a << 6) + (a >> 2));
  x ^= x >> 31;
  x *= 0xbf58476d1ce4e5b9ULL;
  return x ^ (x >> 29);
}

DetectorKind DetectorKindFromName(const std::string& name) {
  if (name == "independent") return DetectorKind::kIndependent;
  if (name == "realistic") return DetectorKind::kRealistic;
  throw std::invalid_argument("unknown detector model '" + name +
                              "' (choose independent or realistic)");
}

std::string DetectorKindName(DetectorKind kind) {
  return kind == DetectorKind::kRealistic ? "realistic" : "independent";
}

const std::vector<RealisticField>& RealisticFields() {
  using R = RealisticDetection;
  static const std::vector<RealisticField> fields = {
      {"base_logit", &R::base_logit},
      {"object_logit_std", &R::object_logit_std},
      {"hard_share", &R::hard_share},
      {"hard_logit", &R::hard_logit},
      {"reference_distance", &R::reference_distance},
      {"distance_logit", &R::distance_logit},
      {"reference_box_pixels", &R::reference_box_pixels},
      {"size_logit", &R::size_logit},
      {"angle_logit", &R::angle_logit},
      {"exposure_ms", &R::exposure_ms},
      {"blur_logit", &R::blur_logit},
      {"occlusion_logit", &R::occlusion_logit},
      {"truncation_logit", &R::truncation_logit},
      {"frame_noise", &R::frame_noise},
      {"wander_seconds", &R::wander_seconds},
      {"wander_logit_std", &R::wander_logit_std},
      {"dropouts_per_minute", &R::dropouts_per_minute},
      {"dropout_seconds", &R::dropout_seconds},
      {"dropout_logit", &R::dropout_logit},
      {"dropout_share", &R::dropout_share},
      {"flips_per_second", &R::flips_per_second},
      {"flip_seconds", &R::flip_seconds},
      {"score_base", &R::score_base},
      {"score_per_logit", &R::score_per_logit},
      {"score_noise", &R::score_noise},
  };
  return fields;
}

int ConfusedClass(int class_id) {
  switch (class_id) {
    case 41:
      return 45;  // cup -> bowl
    case 45:
      return 41;
    case 73:
      return 63;  // book -> laptop
    case 63:
      return 73;
    case 39:
      return 41;  // bottle -> cup
    default:
      return class_id;
  }
}

double ConditionLogit(const RealisticDetection& p, const ViewingConditions& c) {
  double logit = p.base_logit;
  logit += p.distance_logit * std::max(0.0, c.distance - p.reference_distance);
  // Detectors lose small objects on a log scale of their pixel area (feature-map strides);
  // larger than the reference gains nothing.
  logit +=
      p.size_logit * std::min(0.0, std::log(std::max(c.box_pixels, 1.0) / p.reference_box_pixels));
  if (c.has_face) logit += p.angle_logit * (1.0 - std::abs(std::cos(c.view_angle)));
  logit += p.blur_logit * std::max(0.0, c.blur_pixels);
  logit += p.occlusion_logit * std::clamp(c.occlusion, 0.0, 1.0);
  logit += p.truncation_logit * std::clamp(c.truncation, 0.0, 1.0);
  return logit;
}

std::vector<DropoutStretch> MakeDropoutStretches(const RealisticDetection& p, double duration,
                                                 std::uint64_t seed) {
  std::vector<DropoutStretch> stretches;
  if (p.dropouts_per_minute <= 0 || p.dropout_seconds <= 0 || duration <= 0) return stretches;
  std::mt19937_64 rng(SeedMix(seed, 0xd50b0a7ULL));
  std::exponential_distribution<double> gap(p.dropouts_per_minute / 60.0);
  std::exponential_distribution<double> length(1.0 / p.dropout_seconds);
  std::uniform_real_distribution<double> depth(0.5, 1.5);
  double t = gap(rng);
  while (t < duration) {
    DropoutStretch stretch;
    stretch.start = t;
    stretch.end = t + std::clamp(length(rng), p.dropout_seconds, 3.0 * p.dropout_seconds);
    stretch.depth = p.dropout_logit * depth(rng);
    stretches.push_back(stretch);
    t = stretch.end + gap(rng);
  }
  return stretches;
}

RealisticDetector::RealisticDetector(const RealisticDetection& params, double duration,
                                     std::uint64_t seed)
    : params_(params), seed_(seed), dropouts_(MakeDropoutStretches(params, duration, seed)) {}

double RealisticDetector::ObjectLogit(int object_id) const {
  std::mt19937_64 rng(SeedMix(seed_, 0x0b1ec7000ULL + static_cast<std::uint64_t>(object_id)));
  std::normal_distribution<double> spread(0.0, params_.object_logit_std);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double own = spread(rng);
  return own + (uniform(rng) < params_.hard_share ? params_.hard_logit : 0.0);
}

double RealisticDetector::DropoutAt(double t) const {
  for (const DropoutStretch& stretch : dropouts_) {
    if (t >= stretch.start && t < stretch.end) return stretch.depth;
  }
  return 0.0;
}

double RealisticDetector::DropoutAt(double t, int object_id) const {
  for (std::size_t i = 0; i < dropouts_.size(); ++i) {
    const DropoutStretch& stretch = dropouts_[i];
    if (t < stretch.start || t >= stretch.end) continue;
    // Which objects a stretch hits is drawn per stretch and object: the others stay found,
    // so their neighbours' absence is evidence a change detector sees.
    std::mt19937_64 rng(
        SeedMix(SeedMix(seed_, 0xd50b0a7ULL + i), static_cast<std::uint64_t>(object_id)));
    return std::uniform_real_distribution<double>(0.0, 1.0)(rng) < params_.dropout_share
               ? stretch.depth
               : 0.0;
  }
  return 0.0;
}

RealisticDetector::Decision RealisticDetector::Decide(int object_id, int class_id,
                                                      const ViewingConditions& conditions, double t,
                                                      std::int64_t frame) {
  std::mt19937_64 rng(SeedMix(SeedMix(seed_, static_cast<std::uint64_t>(object_id)),
                              static_cast<std::uint64_t>(frame)));
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> gaussian(0.0, 1.0);
  ObjectState& state = objects_[object_id];
  // The wander keeps its stationary spread whatever the frame rate: it decays by
  // exp(-dt / tau) and takes the innovation that restores the variance.
  if (state.last_time < 0) {
    state.wander = params_.wander_logit_std * gaussian(rng);
  } else {
    const double rho = params_.wander_seconds > 0
                           ? std::exp(-std::max(t - state.last_time, 0.0) / params_.wander_seconds)
                           : 0.0;
    state.wander =
        rho * state.wander + std::sqrt(1.0 - rho * rho) * params_.wander_logit_std * gaussian(rng);
  }
  const double dt = state.last_time < 0 ? 0.0 : std::max(t - state.last_time, 0.0);
  state.last_time = t;

  const double steady = ConditionLogit(params_, conditions) + ObjectLogit(object_id);
  const double logit = steady + state.wander + DropoutAt(t, object_id);
  Decision decision;
  // Detected when logit + frame_noise * (standard logistic noise) > 0.
  decision.probability = 1.0 / (1.0 + std::exp(-logit / std::max(params_.frame_noise, 1e-6)));
  decision.detected = uniform(rng) < decision.probability;
  decision.class_id = class_id;
  const double flip_draw = uniform(rng);
  const double flip_length =
      std::exponential_distribution<double>(1.0 / std::max(params_.flip_seconds, 1e-6))(rng);
  const double score_noise = gaussian(rng);
  if (!decision.detected) return decision;
  // A flip starts only on a detection and lasts its drawn time, detected or not, so the
  // wrong class comes back on consecutive detections as a real detector's does.
  if (t >= state.flip_until && ConfusedClass(class_id) != class_id &&
      flip_draw < 1.0 - std::exp(-params_.flips_per_second * dt)) {
    state.flip_until = t + flip_length;
    state.flip_class = ConfusedClass(class_id);
  }
  if (t < state.flip_until) decision.class_id = state.flip_class;
  // The score follows how easy the object is to see, not the momentary wander, so scores
  // of one object stay alike from frame to frame.
  decision.confidence = std::clamp(
      params_.score_base + params_.score_per_logit * steady + params_.score_noise * score_noise,
      0.25, 0.97);
  return decision;
}

}  // namespace ocg::sim
