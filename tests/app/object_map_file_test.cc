// The object layer's part of a map file (src/app/object_map_file.h) on its own: the object
// map, the OCG and the mapper's counters saved after a synthetic table scene's first half
// and loaded into a fresh mapper. Loading and saving again gives the same bytes, and the
// loaded mapper goes on exactly as the one that was saved: same objects, same removals,
// same graph at the end.

#include "object_map_file.h"

#include <gtest/gtest.h>

#include <sstream>

#include "session_file.h"
#include "synthetic_scene.h"
#include "test_support.h"

namespace ocg {
namespace {

constexpr int kKeyframeInterval = 5;

void Feed(const testing::SyntheticScene& scene, int first, int last, ObjectMapper* mapper) {
  for (int frame = first; frame < last; ++frame) {
    const auto f = static_cast<std::size_t>(frame);
    mapper->AddFrame(frame, scene.timestamps[f], scene.T_cw[f], scene.detections[f]);
    if (frame % kKeyframeInterval == 0)
      mapper->AddKeyframe(frame / kKeyframeInterval, scene.timestamps[f], scene.T_cw[f]);
  }
}

std::unique_ptr<ObjectMapper> NewMapper(const testing::SyntheticScene& scene) {
  auto mapper = std::make_unique<ObjectMapper>(ObjectsOptions{}, testing::PaperOptions(),
                                               scene.options.camera, true);
  mapper->RecordObservations();
  return mapper;
}

std::string Save(const ObjectMapper& mapper, const app_detail::ObjectLayerCounters& counters) {
  std::ostringstream out;
  app_detail::SaveObjectMapper(mapper, counters, out);
  return out.str();
}

// The cup is taken away at frame 60; the map is saved at frame 80, while its doubt grows
// (suspicious, not yet removed), so the OCG's state in the file decides the removal.
class ObjectMapFile : public ::testing::Test {
 protected:
  ObjectMapFile() : scene_(testing::SynthesizeScene(testing::TableWithObjects(60))) {
    counters_.keyframes = 16;
    counters_.tracked_frames = 80;
    counters_.change_log = R"({"changes": []})";
  }
  testing::SyntheticScene scene_;
  app_detail::ObjectLayerCounters counters_;
};

TEST_F(ObjectMapFile, LoadingAndSavingAgainGivesTheSameBytesAndTheSameMap) {
  const auto saved = NewMapper(scene_);
  Feed(scene_, 0, 80, saved.get());
  const std::string bytes = Save(*saved, counters_);
  ASSERT_GT(bytes.size(), 1000u);

  const auto loaded = NewMapper(scene_);
  std::istringstream in(bytes);
  const app_detail::ObjectLayerCounters counters =
      app_detail::LoadObjectMapper(in, loaded.get(), app_detail::kMapFileVersion);
  EXPECT_EQ(counters.keyframes, counters_.keyframes);
  EXPECT_EQ(counters.tracked_frames, counters_.tracked_frames);
  EXPECT_EQ(counters.change_log, counters_.change_log);
  EXPECT_EQ(Save(*loaded, counters), bytes);
  EXPECT_EQ(loaded->ObjectsJson(), saved->ObjectsJson());
  EXPECT_EQ(ChangeLogJson(EntriesOf(loaded->Changes())),
            ChangeLogJson(EntriesOf(saved->Changes())));
  EXPECT_EQ(loaded->GraphJson(), saved->GraphJson());
  EXPECT_EQ(loaded->ObservationsJsonl(), saved->ObservationsJsonl());
  EXPECT_EQ(loaded->Stats().keyframes, 16);
  EXPECT_EQ(loaded->LiveObjectCount(), 4u);
}

TEST_F(ObjectMapFile, TheLoadedMapperGoesOnAsTheSavedOne) {
  const auto whole = NewMapper(scene_);
  Feed(scene_, 0, 120, whole.get());
  whole->Finish();

  const auto first_half = NewMapper(scene_);
  Feed(scene_, 0, 80, first_half.get());
  const auto continued = NewMapper(scene_);
  std::istringstream in(Save(*first_half, counters_));
  app_detail::LoadObjectMapper(in, continued.get(), app_detail::kMapFileVersion);
  Feed(scene_, 80, 120, continued.get());
  continued->Finish();

  // The cup was removed on leaving at frame 100, after the load: the doubt it had
  // gathered before was in the file.
  EXPECT_EQ(continued->LiveObjectCount(), 3u);
  EXPECT_EQ(continued->ObjectsJson(), whole->ObjectsJson());
  EXPECT_EQ(ChangeLogJson(EntriesOf(continued->Changes())),
            ChangeLogJson(EntriesOf(whole->Changes())));
  EXPECT_EQ(continued->GraphJson(), whole->GraphJson());
  EXPECT_EQ(continued->ObservationsJsonl(), whole->ObservationsJsonl());
}

TEST_F(ObjectMapFile, AVersion1FileHoldsNoChangeLog) {
  const auto saved = NewMapper(scene_);
  Feed(scene_, 0, 80, saved.get());
  // A version 1 file ends before the change log: what comes after it is not read.
  std::istringstream in(Save(*saved, counters_));
  const auto loaded = NewMapper(scene_);
  const app_detail::ObjectLayerCounters counters =
      app_detail::LoadObjectMapper(in, loaded.get(), 1);
  EXPECT_FALSE(counters.change_log.has_value());
  EXPECT_EQ(loaded->ObjectsJson(), saved->ObjectsJson());
}

TEST_F(ObjectMapFile, ATruncatedStreamIsAnErrorNotAHalfLoadedMap) {
  const auto saved = NewMapper(scene_);
  Feed(scene_, 0, 80, saved.get());
  const std::string bytes = Save(*saved, counters_);
  for (const std::size_t keep :
       {std::size_t{0}, std::size_t{7}, bytes.size() / 2, bytes.size() - 1}) {
    std::istringstream in(bytes.substr(0, keep));
    const auto loaded = NewMapper(scene_);
    EXPECT_THROW(app_detail::LoadObjectMapper(in, loaded.get(), app_detail::kMapFileVersion),
                 std::runtime_error)
        << "kept " << keep << " of " << bytes.size() << " bytes";
  }
}

}  // namespace
}  // namespace ocg
