// ocg_convert_detections: EAO text folder <-> JSON list of detections.

#include <filesystem>
#include <iostream>

#include "cli_common.h"
#include "ocg/core/file_io.h"
#include "ocg/io/detections.h"

int main(int argc, char** argv) {
  CLI::App app{
      "ocg_convert_detections: convert object detections between the EAO text format "
      "(a folder of <timestamp>.txt files, 'class_id x y w h confidence') and the JSON "
      "list format ([{\"file_name\", \"detections\": [{\"category_id\", "
      "\"detection_score\", \"bbox\": [x1, y1, x2, y2]}]}])",
      "ocg_convert_detections"};
  std::string log_level, input, output, prefix = "rgb/", extension = ".png";
  bool lenient = false;
  ocg::tools::AddLogLevelOption(app, &log_level);
  app.add_option("--from", input, "an EAO folder or a .json file")
      ->required()
      ->check(CLI::ExistingPath);
  app.add_option("--to", output, "a .json file (from a folder) or a folder (from a .json file)")
      ->required();
  app.add_option("--image-prefix", prefix, "EAO -> JSON: file_name prefix")->capture_default_str();
  app.add_option("--image-ext", extension, "EAO -> JSON: file_name extension")
      ->capture_default_str();
  app.add_flag("--lenient", lenient, "skip malformed lines with a warning instead of failing");

  return ocg::tools::RunTool(app, argc, argv, log_level, [&] {
    namespace fs = std::filesystem;
    ocg::DetectionReadOptions options;
    options.lenient = lenient;
    if (fs::is_directory(input)) {
      std::vector<ocg::DetectionFrame> frames = ocg::ReadEaoDetectionDir(input, options);
      std::size_t count = 0;
      for (ocg::DetectionFrame& frame : frames) {
        frame.file_name = prefix + frame.file_name + extension;
        count += frame.detections.size();
      }
      ocg::WriteFileAtomically(output, ocg::FormatJsonDetections(frames));
      std::cout << "wrote " << count << " detections of " << frames.size() << " images to "
                << output << "\n";
      return;
    }
    const std::vector<ocg::DetectionFrame> frames = ocg::ReadJsonDetections(input, options);
    // Validate every name before writing anything, so a failure leaves no partial folder.
    for (const ocg::DetectionFrame& frame : frames) {
      if (fs::path(frame.file_name).stem().empty()) {
        throw ocg::FileError(input + ": an image has an empty file_name");
      }
    }
    ocg::CheckWritableFolder(output);
    std::size_t count = 0;
    for (const ocg::DetectionFrame& frame : frames) {
      const std::string stem = fs::path(frame.file_name).stem().string();
      ocg::WriteFileAtomically((fs::path(output) / (stem + ".txt")).string(),
                               ocg::FormatEaoDetections(frame.detections));
      count += frame.detections.size();
    }
    std::cout << "wrote " << count << " detections of " << frames.size() << " images to " << output
              << "/\n";
  });
}
