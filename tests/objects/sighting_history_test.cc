// SightingHistory: an object's sightings bounded, with what the object map asks of the
// whole history kept exact (issue 33: memory grew with every revisit).

#include "ocg/objects/sighting_history.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

namespace ocg {
namespace {

ObjectSighting SightingAt(std::int64_t frame, int class_id = 41, int session = 0) {
  ObjectSighting sighting;
  sighting.frame = frame;
  sighting.box = {10.0 + frame % 7, 20.0, 60.0, 80.0};
  sighting.class_id = class_id;
  sighting.session = session;
  sighting.timestamp = 100.0 + frame / 30.0;
  sighting.crowded = frame % 5 == 0;
  return sighting;
}

std::vector<std::int64_t> FramesOf(const SightingHistory& history) {
  std::vector<std::int64_t> frames;
  for (const ObjectSighting& sighting : history) frames.push_back(sighting.frame);
  return frames;
}

TEST(SightingHistory, BelowItsCapacityEverySightingIsKept) {
  SightingHistory history;
  for (std::int64_t frame = 0; frame < 100; ++frame) history.Add(SightingAt(frame), 100);
  ASSERT_EQ(history.size(), 100u);
  for (std::size_t i = 0; i < history.size(); ++i)
    EXPECT_EQ(history[i].frame, static_cast<std::int64_t>(i));
  EXPECT_EQ(history.level(), 0);
  EXPECT_EQ(history.total(), 100u);
}

// An object seen 20,000 times (a long run revisiting it) keeps at most its capacity, and
// still answers what the object map asks of all of them.
TEST(SightingHistory, AnObjectSeenManyTimesKeepsABoundedSampleAndExactCounts) {
  constexpr std::size_t kCapacity = 64;
  constexpr std::int64_t kSightings = 20000;
  SightingHistory history;
  std::size_t most = 0;
  for (std::int64_t frame = 1; frame <= kSightings; ++frame) {
    // A class flip now and then (the detector's cup for a bowl), and a second session.
    history.Add(SightingAt(frame, frame % 3 == 0 ? 45 : 41, frame > 15000 ? 1 : 0), kCapacity);
    most = std::max(most, history.size());
  }
  EXPECT_LE(most, kCapacity);
  EXPECT_GE(history.size(), kCapacity / 4);
  EXPECT_EQ(history.total(), static_cast<std::size_t>(kSightings));
  EXPECT_EQ(history.uncrowded(), static_cast<std::size_t>(kSightings - kSightings / 5));
  EXPECT_EQ(history.MajorityClass(), 41);
  EXPECT_EQ(history.SessionRange(), std::make_pair(0, 1));
  const SightingHistory::ClassSpan& cup_then = history.spans().at({0, 41});
  EXPECT_DOUBLE_EQ(cup_then.first_timestamp, SightingAt(1).timestamp);
  EXPECT_DOUBLE_EQ(cup_then.last_timestamp, SightingAt(14999).timestamp);
  EXPECT_EQ(history.spans().at({1, 45}).count, static_cast<std::size_t>(20000 / 3 - 15000 / 3));
  // The first and the newest quarter whole, in frame order.
  EXPECT_EQ(history.front().frame, 1);
  EXPECT_EQ(history.back().frame, kSightings);
  const std::vector<std::int64_t> frames = FramesOf(history);
  EXPECT_TRUE(std::is_sorted(frames.begin(), frames.end()));
  for (std::size_t i = frames.size() - kCapacity / 4; i < frames.size(); ++i)
    EXPECT_EQ(frames[i], kSightings - static_cast<std::int64_t>(frames.size() - 1 - i));
  // The rest spread evenly over the run: at least one in every 2^level frames, and that
  // step no wider than the run shared among a quarter of the capacity.
  const std::int64_t step = std::int64_t{1} << history.level();
  EXPECT_LE(step, 4 * kSightings / static_cast<std::int64_t>(kCapacity));
  for (std::size_t i = 0; i + 1 < frames.size(); ++i)
    EXPECT_LE(frames[i + 1] - frames[i], step) << frames[i];
}

// Two objects seen in the same frames keep the same frames, so the object map still sees
// that they were detected together (its SeenTogether compares the sightings' frames).
TEST(SightingHistory, ObjectsSeenInTheSameFramesKeepTheSameFrames) {
  SightingHistory often, seldom;
  for (std::int64_t frame = 1; frame <= 9000; ++frame) {
    often.Add(SightingAt(frame), 64);
    if (frame > 3000 && frame < 6000) seldom.Add(SightingAt(frame, 63), 64);
  }
  ASSERT_GT(often.level(), seldom.level());
  std::set<std::int64_t> common;
  const std::vector<std::int64_t> seldom_frames = FramesOf(seldom);
  for (const std::int64_t frame : FramesOf(often)) {
    if (std::binary_search(seldom_frames.begin(), seldom_frames.end(), frame)) common.insert(frame);
  }
  // Every frame the busier history keeps within the other's span is kept by both.
  for (const std::int64_t frame : FramesOf(often)) {
    if (frame > 3000 && frame < 5900) {
      EXPECT_EQ(common.count(frame), 1u) << frame;
    }
  }
  EXPECT_GE(common.size(), 2u);
}

TEST(SightingHistory, AMergeAddsTheCountsAndStaysBounded) {
  SightingHistory a, b;
  for (std::int64_t frame = 0; frame < 300; ++frame) {
    if (frame % 2 == 0) {
      a.Add(SightingAt(frame, 41), 100);
    } else {
      b.Add(SightingAt(frame, 45, 1), 100);
    }
  }
  a.Merge(b, 100);
  EXPECT_LE(a.size(), 100u);
  EXPECT_EQ(a.total(), 300u);
  EXPECT_EQ(a.MajorityClass(), 41);  // a tie: the lower id
  const std::vector<std::int64_t> frames = FramesOf(a);
  EXPECT_TRUE(std::is_sorted(frames.begin(), frames.end()));
  EXPECT_EQ(a.front().frame, 0);
  EXPECT_EQ(a.back().frame, 299);
  EXPECT_EQ(a.SessionRange(), std::make_pair(0, 1));
  EXPECT_TRUE(a.SharesASessionWith(b));
  SightingHistory later;
  later.Add(SightingAt(400, 41, 2), 100);
  EXPECT_FALSE(later.SharesASessionWith(b));
}

// A span dates an object's sightings as its class with support: the second sighting and
// the second last, so that one stray box before (or after) does not. Spans merged give
// what one span of every sighting gives.
TEST(SightingHistory, AClassSpanDatesItsSightingsBySupport) {
  SightingHistory::ClassSpan span;
  span.Add(50.0);
  EXPECT_EQ(span.SupportedFirst(), 50.0);  // one sighting: its own time
  EXPECT_EQ(span.SupportedLast(), 50.0);
  for (double time : {10.0, 52.0, 51.0, 90.0}) span.Add(time);  // 10 and 90: stray boxes
  EXPECT_EQ(span.first_timestamp, 10.0);
  EXPECT_EQ(span.last_timestamp, 90.0);
  EXPECT_EQ(span.SupportedFirst(), 50.0);
  EXPECT_EQ(span.SupportedLast(), 52.0);
  const std::vector<double> times = {7, 3, 9, 1, 8, 2, 6, 4, 5};
  for (std::size_t split = 0; split <= times.size(); ++split) {
    SightingHistory::ClassSpan all, a, b;
    for (std::size_t i = 0; i < times.size(); ++i) {
      all.Add(times[i]);
      (i < split ? a : b).Add(times[i]);
    }
    a.Merge(b);
    EXPECT_EQ(a.count, all.count);
    EXPECT_EQ(a.SupportedFirst(), 2.0) << "split " << split;
    EXPECT_EQ(a.SupportedLast(), 8.0) << "split " << split;
    EXPECT_EQ(a.first_timestamp, 1.0);
    EXPECT_EQ(a.last_timestamp, 9.0);
  }
}

// VisitFrames finds, frame by frame, the same sightings a search of each frame finds:
// frames before, among, between and after the kept ones, near each other and far apart,
// with two sightings at one frame, over histories of every length up to a few hundred.
TEST(SightingHistory, VisitingFramesFindsWhatASearchOfEachFrameFinds) {
  std::mt19937 random(7);
  for (int length = 0; length < 300; length += 1 + length / 8) {
    SightingHistory history;
    std::int64_t frame = 3;
    for (int i = 0; i < length; ++i) {
      history.Add(SightingAt(frame), 0);
      if (i % 17 == 5) history.Add(SightingAt(frame), 0);  // two boxes at one frame
      frame += 1 + static_cast<std::int64_t>(random() % 4);
    }
    for (int trial = 0; trial < 20; ++trial) {
      std::set<std::int64_t> chosen;
      const int count = 1 + static_cast<int>(random() % 40);
      for (int i = 0; i < count; ++i) {
        // Mostly recent frames (as a keyframe re-poses them), some anywhere, some beyond.
        const std::int64_t span = frame + 10;
        chosen.insert(i % 3 == 0 ? static_cast<std::int64_t>(random() % span)
                                 : frame - static_cast<std::int64_t>(random() % 60));
      }
      const std::vector<std::int64_t> frames(chosen.begin(), chosen.end());
      std::vector<std::pair<std::int64_t, std::size_t>> visited;  // (frame, first index)
      std::size_t sightings = 0;
      history.VisitFrames(frames, [&](std::int64_t at, auto first, auto last) {
        visited.emplace_back(at, static_cast<std::size_t>(first - history.begin()));
        for (auto sighting = first; sighting != last; ++sighting) {
          EXPECT_EQ(sighting->frame, at);
          ++sightings;
        }
      });
      std::vector<std::pair<std::int64_t, std::size_t>> expected;
      std::size_t expected_sightings = 0;
      for (const std::int64_t at : frames) {
        const auto first = std::find_if(history.begin(), history.end(),
                                        [at](const ObjectSighting& s) { return s.frame == at; });
        if (first == history.end()) continue;
        expected.emplace_back(at, static_cast<std::size_t>(first - history.begin()));
        expected_sightings += static_cast<std::size_t>(
            std::count_if(history.begin(), history.end(),
                          [at](const ObjectSighting& s) { return s.frame == at; }));
      }
      EXPECT_EQ(visited, expected) << "length " << length << ", trial " << trial;
      EXPECT_EQ(sightings, expected_sightings);
    }
  }
}

TEST(SightingHistory, ZeroCapacityKeepsAll) {
  SightingHistory history;
  for (std::int64_t frame = 0; frame < 5000; ++frame) history.Add(SightingAt(frame), 0);
  EXPECT_EQ(history.size(), 5000u);
}

TEST(SightingHistory, AHistoryReadBackCountsItsSightings) {
  std::vector<ObjectSighting> sightings = {SightingAt(3, 41), SightingAt(4, 45), SightingAt(9, 45)};
  const SightingHistory history(sightings);
  EXPECT_EQ(history.size(), 3u);
  EXPECT_EQ(history.total(), 3u);
  EXPECT_EQ(history.MajorityClass(), 45);
}

}  // namespace
}  // namespace ocg
