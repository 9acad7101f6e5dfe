#include "ocg/app/pose_given.h"

#include <spdlog/spdlog.h>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "object_layer.h"
#include "ocg/core/statistics.h"
#include "ocg/objects/object_mapper.h"
#include "run_snapshots.h"

namespace ocg {
namespace {

// The colours of the sightings made at frame (a keyframe), from its image when the frame
// list gives one: a keyframe's image is read as it comes (a tenth of the frames), none is
// kept. The pairing of moves weighs them (ChangeLogContext::colour).
struct KeyframeColours {
  std::int64_t images = 0, sightings = 0, unreadable = 0;
  std::string first_unreadable;

  void Set(ObjectMapper& mapper, std::int64_t frame, const std::string& path) {
    const cv::Mat bgr =
        std::filesystem::exists(path) ? cv::imread(path, cv::IMREAD_COLOR) : cv::Mat();
    if (bgr.empty()) {
      if (unreadable++ == 0) first_unreadable = path;
      return;
    }
    ++images;
    sightings += mapper.SetSightingColours(frame, bgr, ColourSignatureOptions{});
  }
  // One warning for the run, not one per keyframe (a frame list of a sequence whose
  // images were left out lists thousands).
  void WarnOfUnreadable() const {
    if (unreadable == 0) return;
    spdlog::warn(
        "{} keyframe image(s) of the frame list could not be read (the first: '{}'): their "
        "sightings give the objects no colour, and moves are paired without it",
        unreadable, first_unreadable);
  }
};

}  // namespace

nlohmann::json MapObjectsAlongTrajectory(const Settings& settings,
                                         const std::vector<PoseGivenFrame>& frames,
                                         DetectionSource& detections, const std::string& folder,
                                         const std::function<void(std::size_t)>& progress,
                                         const RunStop* stop, const SnapshotPolicy& snapshots) {
  ObjectMapper mapper(settings.objects, settings.ocg, settings.camera.model, true);
  app_detail::PoseGivenOutputs outputs(settings, snapshots, folder);
  mapper.RecordObservations();
  const auto start = std::chrono::steady_clock::now();
  std::int64_t used = 0, without_pose = 0, keyframes = 0;
  KeyframeColours colours;
  DurationSummary frame_seconds;  // a summary: memory stays flat on a long run
  bool interrupted = false;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    if (stop != nullptr && stop->Requested()) {
      interrupted = true;
      break;
    }
    const PoseGivenFrame& frame = frames[i];
    if (!frame.T_cw) {
      ++without_pose;
      continue;
    }
    const auto frame_start = std::chrono::steady_clock::now();
    const FrameAssociation association = mapper.AddFrame(
        used, frame.timestamp, *frame.T_cw, detections.DetectionsFor(frame.timestamp_text, {}));
    const bool keyframe = used % settings.objects.keyframe_interval == 0;
    if (keyframe && !frame.image_path.empty() && !association.detections.empty())
      colours.Set(mapper, used, frame.image_path);
    if (keyframe) {
      outputs.BeforeKeyframe(mapper);
      mapper.AddKeyframe(keyframes++, frame.timestamp, *frame.T_cw);
    }
    frame_seconds.Add(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - frame_start).count());
    outputs.AfterFrame(mapper, frame, association, keyframe);
    ++used;
    if (progress) progress(i + 1);
  }
  mapper.Finish();
  colours.WarnOfUnreadable();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  nlohmann::json report = {
      {"frames", frames.size()},
      {"interrupted", interrupted},
      {"frames_used", used},
      {"frames_without_pose", without_pose},
      {"keyframes", keyframes},
      {"colour_signatures",
       {{"keyframe_images", colours.images}, {"sightings", colours.sightings}}},
      {"wall_seconds", seconds},
      {"timing", {{"objects_per_frame", app_detail::Timing(frame_seconds)}}}};
  ChangeLogContext change_log;
  if (!frames.empty()) change_log.session_start = frames.front().timestamp;
  change_log.seen_as_class = mapper.SeenAsClassThisSession();
  change_log.colour = mapper.ColourAppearances(change_log.appearance_options.min_colour_signatures);
  report.update(app_detail::WriteObjectMap(mapper, folder, change_log));
  report["snapshots"] = outputs.Finish(mapper);
  return report;
}

}  // namespace ocg
