#pragma once
// An object's sightings, bounded: a long run that keeps revisiting an object must not keep
// every box it was ever detected in (issue 33: about 0.6 kB a frame on the smoke preset
// played forward and back, without end). What the object map asks of the whole history is
// kept exactly in running counts (how many sightings, how many uncrowded, per class and
// session, first and last timestamps); the boxes themselves (geometry, partial views,
// "seen together") are a bounded sample:
//
// - the first sighting and the newest `capacity / 4` ones, whole;
// - of the rest, those at frames with at least `level()` trailing zero bits (frame numbers
//   as given): one in every 2^level frames, the same frames for every object. The level
//   rises when the history holds more than `capacity`, so the kept boxes stay spread
//   evenly over the run (as Objects.max_rays thins them) and two objects detected in the
//   same frames keep the same ones (ObjectMap's SeenTogether compares frames).
//
// Below capacity nothing is dropped: a run whose objects are never seen more than
// `capacity` times (Objects.max_sightings) behaves as with every sighting kept.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "ocg/core/box2.h"
#include "ocg/core/lie.h"
#include "ocg/objects/colour_signature.h"

namespace ocg {

// A sighting's colour signature, held apart: most sightings never get one (only those at
// keyframes, at the end of a run), and inline it would be most of a sighting's size.
// Reads and assigns as a std::optional<ColourHistogram>.
class SightingColour {
 public:
  SightingColour() = default;
  SightingColour(std::nullopt_t) {}  // NOLINT(google-explicit-constructor): as optional
  SightingColour(const std::optional<ColourHistogram>& colour)  // NOLINT: as optional
      : histogram_(colour ? std::make_shared<const ColourHistogram>(*colour) : nullptr) {}
  explicit operator bool() const { return histogram_ != nullptr; }
  const ColourHistogram& operator*() const { return *histogram_; }
  operator std::optional<ColourHistogram>() const {  // NOLINT: as optional
    return histogram_ ? std::optional<ColourHistogram>(*histogram_) : std::nullopt;
  }

 private:
  std::shared_ptr<const ColourHistogram> histogram_;  // immutable: copies share it
};

struct ObjectSighting {
  std::int64_t frame = 0;
  SE3 T_cw;
  Box2 box;
  bool truncated = false;
  // The box shares area with a more confident box of its class in the frame
  // (BesideAMoreConfidentBoxOfItsClass): its centre may be on the other object (a second
  // box on it, or a box sliding onto it as the view changes). It neither helps a candidate
  // become an object nor keeps an object through the hygiene (Objects.min_sightings); a
  // map object's geometry uses it like any other. Not saved in map files.
  bool crowded = false;
  int class_id = 0;  // as detected (detectors confuse cup and bowl, book and laptop)
  int session = 0;   // the session (map files: 0 for the first run) that saw it
  // The object's colour in the box (BoxColourSignature), set as the sighting is made at an
  // OCG keyframe whose image is known (ObjectMapper::AddFrame, both run kinds).
  SightingColour colour;
  // Seconds, the frame's timestamp (SeenAsClass()). Not saved in map files: 0 in sightings
  // loaded from one.
  double timestamp = 0.0;
};

class SightingHistory {
 public:
  // The sightings of one session as one class: how many, and the timestamps (seconds) of
  // the first two and the last two.
  struct ClassSpan {
    std::size_t count = 0;
    double first_timestamp = 0.0;
    double last_timestamp = 0.0;
    double second_timestamp = 0.0;       // the second earliest (count >= 2)
    double second_last_timestamp = 0.0;  // the second latest (count >= 2)
    // One sighting more, at this time (any order).
    void Add(double timestamp);
    // Another span of the same session and class joins this one.
    void Merge(const ClassSpan& other);
    // When the object was seen as the class with support: the second sighting's time and
    // the second last's (the only one's, of a single sighting). One stray box (a detection
    // of the class somewhere else at the object's place before it came, or after it left)
    // does not date it.
    double SupportedFirst() const { return count >= 2 ? second_timestamp : first_timestamp; }
    double SupportedLast() const { return count >= 2 ? second_last_timestamp : last_timestamp; }

   private:
    // The distinct sightings' times this span holds, in order (up to four).
    std::vector<double> Extremes() const;
  };
  // (session, class id) -> span
  using Spans = std::map<std::pair<int, int>, ClassSpan>;

  SightingHistory() = default;
  // A history of exactly these sightings (map files), in frame order; the counts are
  // theirs.
  explicit SightingHistory(std::vector<ObjectSighting> sightings);

  // A new sighting, at a frame after every kept one's. capacity (at least 8): the
  // sightings kept at most; 0 keeps all.
  void Add(const ObjectSighting& sighting, std::size_t capacity);
  // The counts stay (what SeenAsClass and the change log ask of a removed object whose
  // boxes nothing reads again), and the sightings of session that carry a colour (the
  // pairing's colour of the object; a pose-given run with images gives them as it goes).
  void ForgetSightings(int session);
  // Another history of the same object joins this one: the kept sightings in frame order
  // (merged, then bounded by capacity as Add bounds them), the counts added.
  void Merge(const SightingHistory& other, std::size_t capacity);

  // The kept sightings, in frame order. Changing one changes neither its frame nor what
  // the counts hold (truncated and colour are not counted).
  const std::vector<ObjectSighting>& kept() const { return kept_; }
  std::vector<ObjectSighting>::iterator begin() { return kept_.begin(); }
  std::vector<ObjectSighting>::iterator end() { return kept_.end(); }
  std::vector<ObjectSighting>::const_iterator begin() const { return kept_.begin(); }
  std::vector<ObjectSighting>::const_iterator end() const { return kept_.end(); }
  std::size_t size() const { return kept_.size(); }  // kept; total() for all
  // The kept sightings at some of these frames (sorted, as the kept ones are), frame by
  // frame: visit(frame, first, last) with [first, last) that frame's sightings, for each
  // frame that has some. Costs what the frames hit, not the history's length: a history
  // ending before the first frame is passed at once, and the search from one frame to the
  // next gallops forward from where the last stopped (the frames a keyframe re-poses are
  // mostly recent and near each other).
  template <typename Visit>
  void VisitFrames(const std::vector<std::int64_t>& frames, Visit&& visit);
  bool empty() const { return kept_.empty(); }
  ObjectSighting& operator[](std::size_t i) { return kept_[i]; }
  const ObjectSighting& operator[](std::size_t i) const { return kept_[i]; }
  const ObjectSighting& front() const { return kept_.front(); }  // the first ever
  const ObjectSighting& back() const { return kept_.back(); }    // the newest

  // Every sighting ever added (objects.json's "observations").
  std::size_t total() const { return total_; }
  // Those not crowded (the hygiene's Objects.min_sightings).
  std::size_t uncrowded() const { return uncrowded_; }
  const Spans& spans() const { return spans_; }
  // The most frequent class of every sighting; the lower id on a tie. 0 when empty.
  int MajorityClass() const;
  // Whether some session saw both objects.
  bool SharesASessionWith(const SightingHistory& other) const;
  // The lowest and the highest session that saw it ({0, 0} when empty).
  std::pair<int, int> SessionRange() const;
  // The kept sightings are those at frames with at least this many trailing zero bits
  // (besides the first and the newest).
  int level() const { return level_; }

 private:
  void Count(const ObjectSighting& sighting);
  void Bound(std::size_t capacity);

  std::vector<ObjectSighting> kept_;
  std::size_t total_ = 0;
  std::size_t uncrowded_ = 0;
  Spans spans_;
  int level_ = 0;
};

template <typename Visit>
void SightingHistory::VisitFrames(const std::vector<std::int64_t>& frames, Visit&& visit) {
  if (kept_.empty() || frames.empty() || kept_.back().frame < frames.front()) return;
  const auto before = [](const ObjectSighting& sighting, std::int64_t frame) {
    return sighting.frame < frame;
  };
  auto at = kept_.begin();
  for (const std::int64_t frame : frames) {
    // Gallop: the first sighting at or after frame is within [at + step / 2, at + step].
    std::ptrdiff_t step = 1;
    while (step < kept_.end() - at && at[step - 1].frame < frame) step *= 2;
    at = std::lower_bound(at + step / 2, at + std::min(step, kept_.end() - at), frame, before);
    if (at == kept_.end()) return;
    if (at->frame != frame) continue;
    auto last = at;
    while (last != kept_.end() && last->frame == frame) ++last;
    visit(frame, at, last);
    at = last;
    if (at == kept_.end()) return;
  }
}

}  // namespace ocg
