#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "ocg/ocg/manager.h"
#include "ocg_test_scene.h"

namespace ocg {
namespace {

using testing::LookAt;
using testing::MakeObservation;

// The moved-object story of scenario_test, as a list of observations: object 1 is
// removed at keyframe 6.
std::vector<KeyframeObservation> Story() {
  const SE3 table = LookAt({-2, 0, 0.8}, {0, 0, 0});
  const SE3 shelf = LookAt({8, 0, 0.8}, {10, 0, 0});
  std::vector<KeyframeObservation> story;
  const std::vector<std::pair<SE3, std::vector<ObjectId>>> script = {
      {table, {1, 2, 3}}, {table, {1, 2, 3}}, {shelf, {5, 6}}, {table, {2, 3}},
      {table, {2, 3}},    {table, {2, 3}},    {shelf, {5, 6}}};
  for (std::size_t i = 0; i < script.size(); ++i) {
    story.push_back(
        MakeObservation(static_cast<std::int64_t>(i), script[i].first, script[i].second));
    for (ObjectId id : script[i].second) {
      story.back().updates[id].centroid =
          id < 5 ? Eigen::Vector3d(0.1 * id, 0, 0) : Eigen::Vector3d(10, 0.1 * id, 0);
    }
  }
  return story;
}

TEST(OcgManager, ThreadedGivesTheSameResultAsSequential) {
  OcgManager sequential(testing::PaperOptions(), true);
  OcgManager threaded(testing::PaperOptions(), false, 2);
  for (const KeyframeObservation& observation : Story()) {
    sequential.Submit(observation);
    threaded.Submit(observation);
  }
  threaded.WaitUntilIdle();
  EXPECT_EQ(threaded.Pending(), 0u);
  EXPECT_EQ(threaded.GraphJson(), sequential.GraphJson());
  ASSERT_EQ(threaded.Removals().size(), 1u);
  EXPECT_EQ(threaded.Removals()[0].object_id, 1);
  EXPECT_FALSE(threaded.Status(1).has_value());
}

TEST(OcgManager, ShutdownDrainsTheQueue) {
  auto manager = std::make_unique<OcgManager>(testing::PaperOptions(), false, 1000);
  std::atomic<int> removals{0};
  manager->SetRemovalCallback(
      [&](const KeyframeResult& result) { removals += static_cast<int>(result.removed.size()); });
  const auto story = Story();
  for (int repeat = 0; repeat < 50; ++repeat) {
    for (KeyframeObservation observation : story) {
      observation.keyframe_id += repeat * 100;
      for (ObjectId& id : observation.observed) id += repeat * 100;
      std::map<ObjectId, ObjectGeometryUpdate> updates;
      for (auto& [id, update] : observation.updates) updates[id + repeat * 100] = update;
      observation.updates = updates;
      manager->Submit(observation);
    }
  }
  manager->Shutdown();
  EXPECT_EQ(manager->Pending(), 0u);
  EXPECT_EQ(removals.load(), 50);  // one removal per repetition, none lost
  EXPECT_EQ(manager->Removals().size(), 50u);
  EXPECT_THROW(manager->Submit(story[0]), std::logic_error);
  manager->Shutdown();  // idempotent
}

TEST(OcgManager, BoundedQueueBlocksTheProducer) {
  OcgManager manager(testing::PaperOptions(), false, 2);
  std::atomic<bool> release{false};
  std::atomic<std::size_t> largest_backlog{0};
  manager.SetRemovalCallback([&](const KeyframeResult&) {
    while (!release) std::this_thread::yield();
  });
  std::thread producer([&] {
    for (int repeat = 0; repeat < 3; ++repeat) {
      for (KeyframeObservation observation : Story()) {
        observation.keyframe_id += repeat * 100;
        manager.Submit(observation);
        largest_backlog = std::max(largest_backlog.load(), manager.Pending());
      }
    }
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  // The worker is stuck in the callback at keyframe 6; the producer must be stuck too.
  EXPECT_LE(manager.Pending(), 3u);  // 2 queued + 1 in progress
  release = true;
  producer.join();
  manager.WaitUntilIdle();
  EXPECT_LE(largest_backlog.load(), 3u);
  EXPECT_EQ(manager.Pending(), 0u);
}

TEST(OcgManager, WorkerErrorsReachTheProducer) {
  OcgManager manager(testing::PaperOptions(), false, 4);
  manager.SetRemovalCallback(
      [](const KeyframeResult&) { throw std::runtime_error("object map failed"); });
  for (const KeyframeObservation& observation : Story()) manager.Submit(observation);
  try {
    manager.WaitUntilIdle();
    FAIL() << "the callback's error was lost";
  } catch (const std::runtime_error& error) {
    EXPECT_STREQ(error.what(), "object map failed");
  }
  EXPECT_THROW(manager.Shutdown(), std::runtime_error);
}

TEST(OcgManager, SnapshotsAreConsistentWhileTheWorkerRuns) {
  OcgManager manager(testing::PaperOptions(), false, 8);
  std::atomic<bool> done{false};
  std::thread reader([&] {
    while (!done) {
      const auto snapshot = manager.Snapshot();
      // Objects 2 and 3 are always observed together: their states never differ.
      std::optional<ObjectState> two, three;
      for (const auto& status : snapshot) {
        if (status.id == 2) two = status.state;
        if (status.id == 3) three = status.state;
      }
      if (two && three) {
        ASSERT_EQ(*two, *three);
      }
    }
  });
  for (int repeat = 0; repeat < 200; ++repeat) {
    for (KeyframeObservation observation : Story()) {
      observation.keyframe_id += repeat * 100;
      manager.Submit(observation);
    }
  }
  manager.WaitUntilIdle();
  done = true;
  reader.join();
}

}  // namespace
}  // namespace ocg
