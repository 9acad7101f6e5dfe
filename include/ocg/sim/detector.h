#pragma once
// The realistic detector model: misses correlated in time and with viewing conditions,
// seconds-long dropout stretches, class flips that persist, per-object detectability
// (scene.h, RealisticDetection, lists the parameters). Used by DetectionModel
// (generator.h) when the scene's noise.kind is kRealistic.
//
// Determinism: every random choice comes from the seed given at construction, the object
// id and the frame index; Decide must be called in frame order (the processes have
// memory), and gives the same results for the same calls.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "ocg/sim/scene.h"

namespace ocg::sim {

// "independent" or "realistic"; throws std::invalid_argument naming the choices.
DetectorKind DetectorKindFromName(const std::string& name);
std::string DetectorKindName(DetectorKind kind);

// The numeric fields of RealisticDetection by their scene-file names (seed excluded), so
// reading and writing scene files list them once.
struct RealisticField {
  const char* name;
  double RealisticDetection::*member;
};
const std::vector<RealisticField>& RealisticFields();

// How an object is seen in one frame.
struct ViewingConditions {
  double distance = 1.0;     // camera centre to object centre, metres
  double view_angle = 0.0;   // radians between the line of sight and the normal of the
                             // object's largest vertical face, folded to [0, pi/2]
  bool has_face = false;     // false for cylinders (no preferred view)
  double blur_pixels = 0.0;  // image motion over the exposure, pixels
  double occlusion = 0.0;    // share of the visible-in-image area hidden, [0, 1]
  double truncation = 0.0;   // share of the projected area outside the image, [0, 1]
  double box_pixels = 1e4;   // visible box area, pixels
};

// The logit of detecting an object in these conditions, before its own detectability,
// wander and dropouts: base_logit plus one term per condition (each <= 0).
double ConditionLogit(const RealisticDetection& p, const ViewingConditions& c);

// A stretch [start, end) of seconds where the logit of the objects it hits (a share
// dropout_share of them, drawn per stretch and object) drops by depth (< 0).
struct DropoutStretch {
  double start = 0.0, end = 0.0, depth = 0.0;
};
// The stretches over [0, duration) seconds: a Poisson process of dropouts_per_minute,
// lengths exponential around dropout_seconds clamped to [1, 3] times it, not overlapping.
std::vector<DropoutStretch> MakeDropoutStretches(const RealisticDetection& p, double duration,
                                                 std::uint64_t seed);

// A class a detector mistakes class_id for (itself when there is none): cup<->bowl,
// book<->laptop, bottle->cup.
int ConfusedClass(int class_id);

// Mixes two numbers into a well-spread 64-bit seed (for per-frame and per-object streams).
std::uint64_t SeedMix(std::uint64_t a, std::uint64_t b);

class RealisticDetector {
 public:
  // duration: seconds the dropout schedule covers.
  RealisticDetector(const RealisticDetection& params, double duration, std::uint64_t seed);

  struct Decision {
    bool detected = false;
    int class_id = 0;          // the reported class (flipped or the true one)
    double probability = 0.0;  // of detection, this frame
    double confidence = 0.0;   // score when detected
  };
  // Whether object_id (true class class_id) is detected at time t (seconds) in frame
  // `frame`. Calls for one object come in increasing t.
  Decision Decide(int object_id, int class_id, const ViewingConditions& conditions, double t,
                  std::int64_t frame);

  // The object's own detectability (a logit offset; hard objects are far below 0).
  double ObjectLogit(int object_id) const;
  // The dropout depth in force at t (0 outside the stretches), and for one object (0 also
  // when the stretch spares it).
  double DropoutAt(double t) const;
  double DropoutAt(double t, int object_id) const;
  const std::vector<DropoutStretch>& dropouts() const { return dropouts_; }

 private:
  struct ObjectState {
    double wander = 0.0;  // current AR(1) value, logit
    double last_time = -1.0;
    double flip_until = -1.0;  // seconds; a flip in force before this time
    int flip_class = 0;
  };

  RealisticDetection params_;
  std::uint64_t seed_;
  std::vector<DropoutStretch> dropouts_;
  std::map<int, ObjectState> objects_;
};

}  // namespace ocg::sim
