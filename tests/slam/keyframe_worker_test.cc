#include "ocg/slam/keyframe_worker.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "ocg/core/thread_name.h"

namespace ocg {
namespace {

TEST(KeyFrameWorker, ProcessesEveryKeyFrameInOrderOnAThreadNamedForProfilers) {
  std::vector<KeyFrameId> processed;
  std::string thread_name;
  KeyFrameWorker worker(
      2,
      [&](const KeyFramePtr& keyframe) {
        processed.push_back(keyframe->id);
        thread_name = ThisThreadName();
      },
      "local_mapping");
  worker.Start();
  for (KeyFrameId id = 0; id < 5; ++id) {
    auto keyframe = std::make_shared<KeyFrame>();
    keyframe->id = id;
    worker.Insert(keyframe);
  }
  worker.Stop();
  EXPECT_EQ(processed, (std::vector<KeyFrameId>{0, 1, 2, 3, 4}));
#if defined(__linux__)
  EXPECT_EQ(thread_name, "local_mapping");
#endif
}

}  // namespace
}  // namespace ocg
