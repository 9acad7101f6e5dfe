// ocg_synth: render a synthetic semi-static sequence (TUM layout) with YOLO-like
// detections and full ground truth (docs/synthetic.md).

#include <cstdio>
#include <iostream>
#include <regex>

#include "cli_common.h"
#include "ocg/sim/generator.h"
#include "ocg/sim/scene_io.h"

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
                                       "round_1, round_2, desk_static");
  app.add_option("--scene", scene_path, "a scene file (YAML)")
      ->check(CLI::ExistingFile)
      ->excludes(preset_option);
  app.add_option("--out", output, "output folder");
  app.add_option("--seed", seed, "seed of the preset's layout, camera wobble and detector noise")
      ->capture_default_str();
  app.add_option("--frames", frames, "render only the first N frames (0: all)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--size", size, "image size WxH (intrinsics scaled), e.g. 320x240");
  app.add_flag("--depth", depth, "also write depth/ and depth.txt (16-bit PNG, 5000 per metre)");
  app.add_flag("--perfect", perfect, "no detector noise");
  int keyframe_interval = 10;
  app.add_option("--keyframe-interval", keyframe_interval,
                 "every N-th frame goes into oracle_observations.jsonl (0: none)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--overwrite", overwrite, "replace an existing output folder");
  app.add_flag("--list-presets", list, "print the preset names and exit");

  return ocg::tools::RunTool(app, argc, argv, log_level, [&] {
    if (list) {
      for (const std::string& name : ocg::sim::PresetNames()) std::cout << name << "\n";
      return;
    }
    if (output.empty()) throw std::invalid_argument("--out is required");
    if (preset.empty() == scene_path.empty())
      throw std::invalid_argument("give --preset or --scene");
    ocg::sim::SceneFile file;
    if (!preset.empty()) {
      file.scene = ocg::sim::MakePreset(preset, seed);
      file.moves = ocg::sim::PresetMoves(preset, file.scene, seed);
    } else {
      file = ocg::sim::LoadSceneFile(scene_path);
    }
    ocg::sim::Scene& scene = file.scene;
    if (perfect) scene.noise.perfect = true;
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
    std::printf(
        "  per frame: render %.1f ms, id pass %.1f ms, detections %.1f ms, writing %.1f ms\n",
        1e3 * stats.colour_seconds / stats.frames, 1e3 * stats.ids_seconds / stats.frames,
        1e3 * stats.detect_seconds / stats.frames, 1e3 * stats.write_seconds / stats.frames);
    std::printf(
        "  written to %s/ (rgb/, rgb.txt, groundtruth.txt, detections/, objects_gt.json, "
        "scene.yaml, "
        "camera.yaml, oracle_observations.jsonl%s)\n",
        output.c_str(), depth ? ", depth/" : "");
  });
}
