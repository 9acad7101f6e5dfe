// ocg_synth: render a synthetic semi-static sequence (TUM layout) with YOLO-like
// detections and full ground truth (docs/synthetic.md).

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <regex>

#include "cli_common.h"
#include "ocg/sim/generator.h"
#include "ocg/sim/scene_io.h"

namespace {

namespace fs = std::filesystem;

// FAST statistics of every PNG or JPEG in folder (or folder/rgb), in name order.
void MeasureFolder(const std::string& folder, bool per_frame) {
  const fs::path images =
      fs::is_directory(fs::path(folder) / "rgb") ? fs::path(folder) / "rgb" : fs::path(folder);
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(images)) {
    const std::string extension = entry.path().extension().string();
    if (extension == ".png" || extension == ".jpg" || extension == ".jpeg")
      files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  if (files.empty())
    throw std::invalid_argument("no .png or .jpg images in '" + images.string() + "'");
  std::vector<ocg::sim::FastStatistics> frames;
  for (const fs::path& file : files) {
    const cv::Mat image = cv::imread(file.string(), cv::IMREAD_COLOR);
    if (image.empty()) throw std::runtime_error("cannot read image '" + file.string() + "'");
    frames.push_back(ocg::sim::MeasureFast(image));
    if (per_frame) {
      std::printf("%s %d %.3f\n", file.filename().string().c_str(), frames.back().corners,
                  frames.back().cell_share);
    }
  }
  const ocg::sim::FastSummary summary = ocg::sim::Summarize(frames);
  std::printf(
      "%s: %d images, FAST corners per frame mean %.0f min %d max %d, cells with corners mean "
      "%.1f %% min %.1f %%\n",
      images.string().c_str(), summary.frames, summary.mean_corners, summary.min_corners,
      summary.max_corners, 100 * summary.mean_cell_share, 100 * summary.min_cell_share);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "ocg_synth: render a synthetic semi-static sequence in TUM format, with detections "
      "in the EAO text format, objects_gt.json, groundtruth.txt and camera.yaml",
      "ocg_synth"};
  std::string log_level, preset, scene_path, output, size;
  std::uint64_t seed = 1;
  int frames = 0;
  bool depth = false, overwrite = false, list = false, perfect = false;
  ocg::tools::AddLogLevelOption(app, &log_level);
  auto* preset_option = app.add_option("--preset", preset,
                                       "a built-in scene: smoke, straight_1, straight_2, "
                                       "round_1, round_2, desk_static, session_a; with "
                                       "--session-of: session_b or a room preset");
  auto* scene_option = app.add_option("--scene", scene_path, "a scene file (YAML)")
                           ->check(CLI::ExistingFile)
                           ->excludes(preset_option);
  std::string session_of;
  app.add_option("--session-of", session_of,
                 "render a later visit of the scene rendered into this folder (its scene.yaml): "
                 "objects moved, removed or added between the visits as --preset says (default "
                 "session_b: 4 moves, 1 removal, 1 addition; a room preset: its changes), drawn "
                 "from --seed; the camera starts half a lap further on")
      ->check(CLI::ExistingDirectory)
      ->excludes(scene_option);
  app.add_option("--out", output, "output folder");
  app.add_option("--seed", seed, "seed of the preset's layout, camera wobble and detector noise")
      ->capture_default_str();
  app.add_option("--frames", frames, "render only the first N frames (0: all)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--size", size, "image size WxH (intrinsics scaled), e.g. 320x240");
  app.add_flag("--depth", depth, "also write depth/ and depth.txt (16-bit PNG, 5000 per metre)");
  app.add_flag("--perfect", perfect, "no detector noise");
  std::string detector;
  std::uint64_t detector_seed = 0;
  bool detections_only = false;
  app.add_option(
      "--detector", detector,
      "independent (default: per-frame misses, short bursts) or realistic (misses correlated "
      "in time and with distance, angle, blur, occlusion and size; seconds-long dropouts; "
      "persistent class flips; hard objects); overrides the scene file's noise.model");
  auto* detector_seed_option = app.add_option(
      "--detector-seed", detector_seed,
      "realistic detector: mixed with --seed, other detections of the same scene; overrides "
      "the scene file's noise.realistic.seed");
  app.add_flag("--detections-only", detections_only,
               "write no images (rgb/, rgb.txt, depth/): detections and ground truth only, "
               "for measuring a detector model (tools/detection_stats.py)");
  std::string look;
  double rolling_shutter_ms = -1;
  app.add_option("--look", look,
                 "procedural (default: dense saturated textures, ideal pinhole) or realistic "
                 "(natural materials, motion blur, auto-exposure, vignetting, TUM fr1 lens "
                 "distortion, sensor noise); overrides the scene file's look.kind");
  app.add_option("--rolling-shutter", rolling_shutter_ms,
                 "realistic look: row readout time in ms (0: global shutter)")
      ->check(CLI::Range(0.0, 100.0));
  int keyframe_interval = 10;
  app.add_option("--keyframe-interval", keyframe_interval,
                 "every N-th frame goes into oracle_observations.jsonl (0: none)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--overwrite", overwrite, "replace an existing output folder");
  app.add_flag("--list-presets", list, "print the preset names and exit");
  std::string measure;
  bool per_frame = false;
  app.add_option("--measure", measure,
                 "print FAST corners per frame and the share of 8x6 grid cells with corners "
                 "(threshold 20 as ORBextractor.iniThFAST, 16-pixel border as the ORB extractor) "
                 "of the images in a folder (its rgb/ subfolder if there is one), and exit")
      ->check(CLI::ExistingDirectory);
  app.add_flag("--per-frame", per_frame, "with --measure: one line per image");

  return ocg::tools::RunTool(app, argc, argv, log_level, [&] {
    if (list) {
      for (const std::string& name : ocg::sim::PresetNames()) std::cout << name << "\n";
      std::cout << "session_b (with --session-of)\n";
      return;
    }
    if (!measure.empty()) {
      MeasureFolder(measure, per_frame);
      return;
    }
    if (output.empty()) throw std::invalid_argument("--out is required");
    ocg::sim::SceneFile file;
    if (!session_of.empty()) {
      const ocg::sim::SceneFile previous = ocg::sim::LoadSceneFile(session_of + "/scene.yaml");
      file.scene = ocg::sim::MakeLaterVisit(
          previous.scene, ocg::sim::PresetVisitChanges(preset.empty() ? "session_b" : preset),
          seed);
    } else if (preset.empty() == scene_path.empty()) {
      throw std::invalid_argument("give --preset or --scene");
    } else if (!preset.empty()) {
      file.scene = ocg::sim::MakePreset(preset, seed);
      file.moves = ocg::sim::PresetMoves(preset, file.scene, seed);
    } else {
      file = ocg::sim::LoadSceneFile(scene_path);
    }
    ocg::sim::Scene& scene = file.scene;
    if (perfect) scene.noise.perfect = true;
    if (!detector.empty()) scene.noise.kind = ocg::sim::DetectorKindFromName(detector);
    if (detector_seed_option->count() > 0) {
      if (scene.noise.kind != ocg::sim::DetectorKind::kRealistic)
        throw std::invalid_argument("--detector-seed needs --detector realistic");
      scene.noise.realistic.seed = detector_seed;
    }
    if (!look.empty()) scene.look.kind = ocg::sim::LookKindFromName(look);
    if (rolling_shutter_ms >= 0) {
      if (!scene.look.realistic())
        throw std::invalid_argument("--rolling-shutter needs --look realistic");
      scene.look.rolling_shutter_ms = rolling_shutter_ms;
    }
    if (!size.empty()) {
      std::smatch match;
      if (!std::regex_match(size, match, std::regex(R"((\d+)x(\d+))"))) {
        throw std::invalid_argument("--size must look like 640x480, got '" + size + "'");
      }
      const double sx = std::stod(match[1]) / scene.camera.width;
      const double sy = std::stod(match[2]) / scene.camera.height;
      scene.camera.fx *= sx;
      scene.camera.cx = (scene.camera.cx + 0.5) * sx - 0.5;
      scene.camera.fy *= sy;
      scene.camera.cy = (scene.camera.cy + 0.5) * sy - 0.5;
      scene.camera.width = std::stoi(match[1]);
      scene.camera.height = std::stoi(match[2]);
      scene.noise.min_visible_pixels *= sx * sy;
      scene.noise.small_box_pixels *= sx * sy;
    }
    ocg::sim::SceneRenderer renderer(scene);
    if (!file.moves.empty()) {
      std::cout << "scheduling " << file.moves.size() << " change(s) at unseen moments...\n";
      ocg::sim::ScheduleMoves(scene, file.moves, renderer);  // keeps renderer in step
    }
    ocg::sim::GeneratorOptions options;
    options.max_frames = frames;
    options.write_depth = depth;
    options.overwrite = overwrite;
    options.keyframe_interval = keyframe_interval;
    options.write_images = !detections_only;
    if (detections_only && depth)
      throw std::invalid_argument("--depth needs images: drop --detections-only");
    const ocg::sim::GenerationStats stats = ocg::sim::Generate(renderer, output, options);
    std::printf("ocg_synth: %s, %d frames in %.1f s (%.1f frames/s)\n", scene.name.c_str(),
                stats.frames, stats.seconds, stats.frames / std::max(stats.seconds, 1e-9));
    std::printf(
        "  detections %zu (%.2f per frame): visible objects %.2f, missed %.2f, false positives "
        "%.2f, "
        "duplicates %.2f per frame\n",
        stats.detections, double(stats.detections) / stats.frames,
        double(stats.visible) / stats.frames, double(stats.missed) / stats.frames,
        double(stats.false_positives) / stats.frames, double(stats.duplicates) / stats.frames);
    if (scene.look.realistic()) {
      std::printf("  look realistic: exposure.txt lists each frame's exposure and gain\n");
    }
    if (!scene.walkers.empty()) {
      std::printf(
          "  walkers: %zu passes; in view in %d frames (%.0f %%), covering a quarter of the "
          "image or more in %d, at most %.0f %% (walkers.txt)\n",
          scene.walkers.size(), stats.walker_frames, 100.0 * stats.walker_frames / stats.frames,
          stats.walker_quarter_frames, 100.0 * stats.walker_coverage_max);
    }
    std::printf(
        "  per frame: render %.1f ms, id pass %.1f ms, detections %.1f ms, writing %.1f ms\n",
        1e3 * stats.colour_seconds / stats.frames, 1e3 * stats.ids_seconds / stats.frames,
        1e3 * stats.detect_seconds / stats.frames, 1e3 * stats.write_seconds / stats.frames);
    std::printf(
        "  written to %s/ (%sgroundtruth.txt, detections/, objects_gt.json, scene.yaml, "
        "camera.yaml, oracle_observations.jsonl%s)\n",
        output.c_str(), detections_only ? "" : "rgb/, rgb.txt, ", depth ? ", depth/" : "");
  });
}
