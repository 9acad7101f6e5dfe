#include "ocg/app/pose_given.h"

#include <spdlog/spdlog.h>
#include <chrono>
#include <cstdint>
#include <string>

#include "keyframe_colours.h"
#include "object_layer.h"
#include "ocg/core/statistics.h"
#include "ocg/objects/object_mapper.h"
#include "run_snapshots.h"

namespace ocg {

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
  app_detail::KeyframeColours colours;  // a keyframe's image is read as it comes, none kept
  DurationSummary frame_seconds;        // a summary: memory stays flat on a long run
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
    const bool keyframe = used % settings.objects.keyframe_interval == 0;
    const std::vector<Detection> boxes = detections.DetectionsFor(frame.timestamp_text, {});
    cv::Mat colour;
    if (keyframe && !boxes.empty()) {
      app_detail::FrameColourImage image(frame.image_path, cv::Mat());
      colour = colours.ImageFor(image);
    }
    const FrameAssociation association =
        mapper.AddFrame(used, frame.timestamp, *frame.T_cw, boxes, nullptr, colour);
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
  nlohmann::json report = {{"frames", frames.size()},
                           {"interrupted", interrupted},
                           {"frames_used", used},
                           {"frames_without_pose", without_pose},
                           {"keyframes", keyframes},
                           {"colour_signatures", colours.Report(mapper.Stats())},
                           {"wall_seconds", seconds},
                           {"timing",
                            {{"objects_per_frame", app_detail::Timing(frame_seconds)},
                             {"colour_per_keyframe_image", colours.Timing(mapper.Stats())}}}};
  ChangeLogContext change_log;
  if (!frames.empty()) change_log.session_start = frames.front().timestamp;
  change_log.seen_as_class = mapper.SeenAsClassThisSession();
  change_log.colour = mapper.ColourAppearances(change_log.appearance_options.min_colour_signatures);
  report.update(app_detail::WriteObjectMap(mapper, folder, change_log));
  report["snapshots"] = outputs.Finish(mapper);
  return report;
}

}  // namespace ocg
