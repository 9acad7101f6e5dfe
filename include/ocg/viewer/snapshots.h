#pragma once
// PNG snapshots of a run: when to take them (`--snapshots final|every:N|none`) and a
// writer that renders map views and frame views into a folder.
//
// Threading: a SnapshotWriter owns its renderer's GL context; use it from one thread.

#include <memory>
#include <string>
#include <vector>

#include "ocg/viewer/map_view.h"

namespace ocg {

struct SnapshotPolicy {
  bool final = true;        // the map views and the last frame at the end
  int every_keyframes = 0;  // also every N SLAM keyframes (0: never)
  bool Enabled() const { return final || every_keyframes > 0; }
};
// "final", "every:N" (N >= 1; implies final) or "none". Throws std::invalid_argument
// saying what is accepted.
SnapshotPolicy ParseSnapshotPolicy(const std::string& text);

class SnapshotWriter {
 public:
  // The folder is created on the first write. The GL context is made on first use.
  SnapshotWriter(std::string folder, ViewerOptions options);
  ~SnapshotWriter();
  SnapshotWriter(const SnapshotWriter&) = delete;
  SnapshotWriter& operator=(const SnapshotWriter&) = delete;

  // Deletes the PNG files a previous run left in the folder (a rerun into the same output
  // folder must not mix two runs' snapshots). Other files are kept.
  void RemoveOldSnapshots();
  // <prefix>_<viewpoint>.png for each viewpoint; returns the paths written.
  std::vector<std::string> WriteMapViews(const MapScene& scene, const std::string& prefix,
                                         const std::vector<MapViewpoint>& viewpoints);
  // <name>.png, atomically (a temporary file renamed). Returns the path.
  std::string WriteImage(const cv::Mat& image, const std::string& name);
  const std::string& folder() const { return folder_; }

 private:
  std::string folder_;
  ViewerOptions options_;
  std::unique_ptr<Renderer> renderer_;
};

}  // namespace ocg
