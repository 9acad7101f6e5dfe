#include "ocg/app/live_feed.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <stdexcept>
#include <vector>

namespace ocg {
namespace {

// A clock that only moves when the feed sleeps or the "system" works.
struct FakeTime {
  double now = 100.0;
  LiveFeed Feed(std::vector<double> timestamps) {
    return LiveFeed(
        std::move(timestamps), [this] { return now; },
        [this](double until) { now = std::max(now, until); });
  }
};

// Feeds every image to a "system" that takes work_seconds(i) for image i; returns the
// indices it was handed.
std::vector<std::size_t> Drive(LiveFeed& feed, FakeTime& time,
                               const std::function<double(std::size_t)>& work_seconds) {
  std::vector<std::size_t> delivered;
  while (const auto i = feed.Next()) {
    delivered.push_back(*i);
    time.now += work_seconds(*i);
  }
  return delivered;
}

std::vector<double> TenFramesAt10Hz() {
  std::vector<double> timestamps;
  for (int i = 0; i < 10; ++i) timestamps.push_back(5.0 + 0.1 * i);
  return timestamps;
}

TEST(LiveFeed, ASystemFasterThanTheCameraGetsEveryImageWhenItIsDue) {
  FakeTime time;
  LiveFeed feed = time.Feed(TenFramesAt10Hz());
  std::vector<std::size_t> delivered;
  while (const auto i = feed.Next()) {
    // Handed over at its capture time, not before (the camera has not taken it yet).
    EXPECT_NEAR(time.now, 100.0 + 0.1 * static_cast<double>(*i), 1e-9);
    delivered.push_back(*i);
    time.now += 0.03;  // tracking
  }
  EXPECT_EQ(delivered, (std::vector<std::size_t>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9}));
  EXPECT_TRUE(feed.Dropped().empty());
  EXPECT_EQ(feed.Report()["frames_dropped"], 0);
  EXPECT_NEAR(feed.Report()["lag_ms"]["max"].get<double>(), 0.0, 1e-6);
}

TEST(LiveFeed, AnImageReplacedWhileTheSystemWasBusyIsDropped) {
  FakeTime time;
  LiveFeed feed = time.Feed(TenFramesAt10Hz());
  // Frame 2 takes 2.5 frame periods: when the system is ready again (0.45 s after the
  // start) image 3 (due 0.3 s) was replaced by image 4 (due 0.4 s), which is late.
  const std::vector<std::size_t> delivered =
      Drive(feed, time, [](std::size_t i) { return i == 2 ? 0.25 : 0.01; });
  EXPECT_EQ(feed.Dropped(), std::vector<std::size_t>{3});
  EXPECT_EQ(delivered, (std::vector<std::size_t>{0, 1, 2, 4, 5, 6, 7, 8, 9}));
  EXPECT_EQ(feed.Delivered(), 9u);
  const nlohmann::json report = feed.Report();
  EXPECT_EQ(report["frames_dropped"], 1);
  EXPECT_EQ(report["first_dropped_frames"], nlohmann::json::array({3}));
  EXPECT_NEAR(report["lag_ms"]["max"].get<double>(), 50.0, 1e-6);  // image 4, 0.05 s late
}

// What the image reader asks before decoding an image ahead: Replaced is true exactly
// for the images the feed then drops, never for one it delivers.
TEST(LiveFeed, ReplacedTellsAheadWhichImagesWillBeDropped) {
  FakeTime time;
  LiveFeed feed = time.Feed(TenFramesAt10Hz());
  EXPECT_FALSE(feed.Replaced(0));                       // the camera has not started
  std::vector<std::vector<std::size_t>> said_replaced;  // after each image's work
  std::vector<std::size_t> delivered;
  while (const auto i = feed.Next()) {
    EXPECT_FALSE(feed.Replaced(*i)) << "image " << *i << " is being delivered";
    delivered.push_back(*i);
    time.now += *i == 2 ? 0.25 : (*i == 6 ? 0.32 : 0.01);
    said_replaced.emplace_back();
    for (std::size_t k = 0; k < 10; ++k) {
      if (feed.Replaced(k)) said_replaced.back().push_back(k);
    }
  }
  EXPECT_EQ(feed.Dropped(), (std::vector<std::size_t>{3, 7, 8}));
  EXPECT_EQ(delivered, (std::vector<std::size_t>{0, 1, 2, 4, 5, 6, 9}));
  // After image 2's work (0.45 s) image 3 is replaced by image 4, not yet by 5.
  EXPECT_EQ(said_replaced[2], (std::vector<std::size_t>{3}));
  // After image 6's work (0.92 s): 7 and 8 replaced, 9 the last image, never replaced.
  EXPECT_EQ(said_replaced[5], (std::vector<std::size_t>{3, 7, 8}));
  for (std::size_t k = 0; k < 10; ++k) {
    const bool dropped = std::count(feed.Dropped().begin(), feed.Dropped().end(), k) > 0;
    EXPECT_EQ(feed.Replaced(k), dropped) << "image " << k;
  }
}

TEST(LiveFeed, ASystemSlowerThanTheCameraGetsTheNewestImageEachTime) {
  FakeTime time;
  LiveFeed feed = time.Feed(TenFramesAt10Hz());
  // A little over two frame periods per image.
  const std::vector<std::size_t> delivered = Drive(feed, time, [](std::size_t) { return 0.21; });
  // The last image has no successor to replace it: it is handed over, late.
  EXPECT_EQ(delivered, (std::vector<std::size_t>{0, 2, 4, 6, 8, 9}));
  EXPECT_EQ(feed.Dropped(), (std::vector<std::size_t>{1, 3, 5, 7}));
}

TEST(LiveFeed, DecreasingTimestampsAreRefused) {
  EXPECT_THROW(LiveFeed({0.0, 0.2, 0.1}), std::invalid_argument);
}

}  // namespace
}  // namespace ocg
