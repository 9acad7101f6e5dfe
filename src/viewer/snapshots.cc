#include "ocg/viewer/snapshots.h"

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

#include "ocg/core/file_io.h"

namespace ocg {

SnapshotPolicy ParseSnapshotPolicy(const std::string& text) {
  SnapshotPolicy policy;
  if (text == "final") return policy;
  if (text == "none") {
    policy.final = false;
    return policy;
  }
  const std::string prefix = "every:";
  if (text.rfind(prefix, 0) == 0) {
    const std::string number = text.substr(prefix.size());
    std::size_t used = 0;
    int every = 0;
    try {
      every = std::stoi(number, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == number.size() && !number.empty() && every >= 1) {
      policy.every_keyframes = every;
      return policy;
    }
  }
  throw std::invalid_argument("--snapshots: '" + text +
                              "' is not one of final, every:N (N >= 1 keyframes), none");
}

SnapshotWriter::SnapshotWriter(std::string folder, ViewerOptions options)
    : folder_(std::move(folder)), options_(options) {
  options_.Check();
}

SnapshotWriter::~SnapshotWriter() = default;

void SnapshotWriter::RemoveOldSnapshots() {
  namespace fs = std::filesystem;
  std::error_code error;
  if (!fs::is_directory(folder_, error)) return;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder_)) {
    if (entry.is_regular_file() && entry.path().extension() == ".png") {
      fs::remove(entry.path(), error);
      if (error) {
        throw FileError("cannot remove the old snapshot '" + entry.path().string() +
                        "': " + error.message());
      }
    }
  }
}

std::vector<std::string> SnapshotWriter::WriteMapViews(
    const MapScene& scene, const std::string& prefix, const std::vector<MapViewpoint>& viewpoints) {
  if (!renderer_) {
    renderer_ = std::make_unique<Renderer>(options_.snapshot_width, options_.snapshot_height);
  }
  std::vector<std::string> paths;
  for (MapViewpoint viewpoint : viewpoints) {
    paths.push_back(WriteImage(RenderMapView(*renderer_, scene, options_, viewpoint),
                               prefix + "_" + ToString(viewpoint)));
  }
  return paths;
}

std::string SnapshotWriter::WriteImage(const cv::Mat& image, const std::string& name) {
  EnsureDirectory(folder_);
  std::vector<unsigned char> png;
  if (!cv::imencode(".png", image, png)) {
    throw std::runtime_error("cannot encode snapshot '" + name + "' as PNG");
  }
  const std::string path = folder_ + "/" + name + ".png";
  WriteFileAtomically(path, std::string(png.begin(), png.end()));
  return path;
}

}  // namespace ocg
