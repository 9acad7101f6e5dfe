// ocg_slam: monocular SLAM on a TUM, EuRoC or KITTI sequence; writes the keyframe and
// camera trajectories (TUM format) and run.json (docs/slam.md). `ocg_slam objects` builds
// the object map from a given trajectory and detections alone (docs/objects.md). The
// options are parsed here; the runs are the sequence runner's (ocg/app/sequence_runner.h).

#include <signal.h>
#include <unistd.h>

#include <iostream>

#include "cli_common.h"
#include "ocg/app/run_stop.h"
#include "ocg/app/sequence_runner.h"
#include "settings_command.h"

namespace {

// The signal that stopped the run (0: none); the exit code is 128 + it.
volatile sig_atomic_t stop_signal = 0;

// SIGINT, SIGTERM: the first asks the run to stop after the frame in hand and write
// everything (RunStop); a second exits at once. Only async-signal-safe calls.
extern "C" void OnStopSignal(int signal) {
  const auto say = [](const char* text, std::size_t length) {
    if (::write(STDERR_FILENO, text, length) < 0) return;
  };
  if (ocg::ProcessRunStop().Request() > 1) {
    static const char kNow[] = "\nocg_slam: second signal: exiting at once, outputs not written\n";
    say(kNow, sizeof kNow - 1);
    ::_exit(128 + signal);
  }
  stop_signal = signal;
  static const char kStop[] =
      "\nocg_slam: stopping after the frame in hand, then writing every output and the map "
      "(a second signal exits at once)\n";
  say(kStop, sizeof kStop - 1);
}

void StopOnSignals() {
  struct sigaction action {};
  action.sa_handler = OnStopSignal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ocg_slam: monocular SLAM (docs/slam.md)", "ocg_slam"};
  std::string log_level;
  ocg::tools::AddLogLevelOption(app, &log_level);
  app.require_subcommand(1);
  app.fallthrough();  // --log-level may follow the subcommand too
  auto* run = app.add_subcommand("run", "run on an image sequence");
  ocg::SlamRunRequest run_request;
  run->add_option("--settings", run_request.settings, "settings file (ours or ORB-SLAM2's)")
      ->required()
      ->check(CLI::ExistingFile);
  run->add_option("--sequence", run_request.sequence, "sequence folder")
      ->required()
      ->check(CLI::ExistingDirectory);
  run->add_option("--format", run_request.format,
                  "tum (rgb.txt), euroc (mav0/) or kitti (image_0/, times.txt, calib.txt)")
      ->capture_default_str()
      ->check(CLI::IsMember({"tum", "euroc", "kitti"}));
  auto* detections_option =
      run->add_option("--detections", run_request.detections.files,
                      "detections: a folder of <timestamp>.txt files (EAO format) or a JSON "
                      "list file (docs/objects.md): maps objects too, writes objects.json, "
                      "changes.json, ocg.json")
          ->check(CLI::ExistingPath);
  run->add_flag("--detect", run_request.detections.detect,
                "detect objects on each frame with the detector network (docs/detector.md), "
                "on the image reader thread; maps objects as --detections does")
      ->excludes(detections_option);
  run->add_option("--model", run_request.detections.model,
                  "--detect: the detector, an .onnx file (default: the one tools/get_detector.sh "
                  "builds)");
  run->add_option("--detect-score", run_request.detections.detect_score,
                  "--detect: minimum confidence of a box (default: the model's, 0.4 for NanoDet)")
      ->check(CLI::Range(0.0, 1.0));
  run->add_option("--out", run_request.output, "output folder")->required();
  run->add_option("--max-frames", run_request.feed.max_frames, "stop after N frames (0: all)")
      ->check(CLI::NonNegativeNumber);
  run->add_option("--vocabulary", run_request.vocabulary,
                  "vocabulary file (overrides Vocabulary.path)");
  run->add_flag("--lenient", run_request.detections.lenient,
                "skip malformed detection lines with a warning instead of failing");
  run->add_option("--snapshots", run_request.snapshots,
                  "PNG snapshots under OUT/snapshots/: final, every:N (also every N "
                  "keyframes) or none; default: final, or every:Viewer.every_keyframes");
  auto* mode_option =
      run->add_option("--mode", run_request.mode,
                      "OCG.mode override for the object layer (off, visibility, paper, ...)");
  run->add_option("--modes", run_request.modes,
                  "several OCG modes, comma-separated, from one SLAM run: each mode's run "
                  "folder is OUT/<mode>/ (sequential mode, needs --detections, cannot continue a "
                  "--load-map)")
      ->excludes(mode_option);
  run->add_option("--read-ahead", run_request.feed.read_ahead,
                  "decode up to N images ahead, and extract their ORB features and detections, "
                  "on a thread of their own (0: decode each when "
                  "it is due, on the tracking thread); default: 4 when the run may use two "
                  "cores or more, else 0")
      ->check(CLI::NonNegativeNumber);
  run_request.feed.status_seconds = 10.0;
  run->add_option("--progress-seconds", run_request.feed.status_seconds,
                  "when stdout is not a terminal, log the progress (frames, keyframes, map "
                  "points, objects, resident memory) every this many seconds (0: never)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  run->add_flag(
      "--realtime", run_request.feed.realtime,
      "feed images at the pace of their timestamps, as a live camera: an image replaced by "
      "the next before tracking was ready is dropped (counted in run.json's feed)");
  run->add_option("--load-map", run_request.load_map,
                  "map file to continue (docs/sessions.md): relocalize in it, then track and "
                  "map in its coordinates as its next session")
      ->check(CLI::ExistingFile);
  run->add_option("--save-map", run_request.save_map,
                  "write the whole state at the end to this map file (SLAM map, objects, OCG, "
                  "settings)");

  auto* objects = app.add_subcommand(
      "objects",
      "pose-given mode: build and maintain the object map from a trajectory and detections, no "
      "images (writes objects.json, changes.json, ocg.json, run.json, the trajectories and "
      "snapshots)");
  ocg::PoseGivenRequest objects_request;
  objects
      ->add_option("--trajectory", objects_request.trajectory,
                   "camera poses, TUM format (camera to world)")
      ->required()
      ->check(CLI::ExistingFile);
  objects
      ->add_option("--detections", objects_request.detections.files,
                   "a folder of <timestamp>.txt detection files (EAO format) or a JSON list file")
      ->required()
      ->check(CLI::ExistingPath);
  objects
      ->add_option("--settings", objects_request.settings,
                   "settings file (camera, Objects.*, OCG.*)")
      ->required()
      ->check(CLI::ExistingFile);
  objects
      ->add_option(
          "--frames", objects_request.frames,
          "image list (rgb.txt) giving the frames (their keyframes' images, read in colour, "
          "pair moved objects by colour); default: the detection files")
      ->check(CLI::ExistingFile);
  objects->add_option("--out", objects_request.output, "output folder")->required();
  objects->add_option("--mode", objects_request.mode,
                      "OCG.mode override (off, visibility, paper, ...)");
  objects
      ->add_option("--snapshots", objects_request.snapshots,
                   "PNG snapshots under OUT/snapshots/ as a run takes them: final, every:N "
                   "(also every N OCG keyframes) or none (docs/viewer.md)")
      ->capture_default_str();
  objects->add_flag("--lenient", objects_request.detections.lenient,
                    "skip malformed detection lines with a warning instead of failing");

  ocg::tools::SettingsCommand settings_command;
  ocg::tools::AddSettingsCommand(app, &settings_command);

  const int code = ocg::tools::RunTool(app, argc, argv, log_level, [&] {
    if (settings_command.app->parsed()) {
      RunSettingsCommand(settings_command);
      return;
    }
    if (objects->parsed()) {
      objects_request.progress_line = true;
      objects_request.stop = &ocg::ProcessRunStop();
      objects_request.before_frames = StopOnSignals;
      ocg::RunPoseGiven(objects_request, std::cout);
      return;
    }
    run_request.feed.progress_line = true;
    run_request.stop = &ocg::ProcessRunStop();
    // From the first frame on, a signal stops the run cleanly (RunStop): no frame after
    // the one in hand, then everything is written as at the end.
    run_request.before_frames = StopOnSignals;
    ocg::RunSlamOnSequence(run_request, std::cout);
    if (stop_signal != 0)
      std::cout << "the run was stopped by a signal: run.json says interrupted\n";
  });
  // A stopped run wrote everything, but did not see all its frames: scripts must know.
  return code == 0 && stop_signal != 0 ? 128 + stop_signal : code;
}
