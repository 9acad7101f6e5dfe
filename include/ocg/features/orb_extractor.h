#pragma once
// ORB features as ORB-SLAM2 extracts them: a scale pyramid, FAST per cell with a fallback
// threshold, a quadtree that spreads the keypoints over each level, intensity-centroid
// orientation and 256-bit steered BRIEF descriptors (OpenCV's pattern, computed by
// cv::ORB on our keypoints, so that ORB-SLAM2 vocabularies describe the same words).

#include <Eigen/Core>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "ocg/core/camera.h"
#include "ocg/features/cell_split.h"
#include "ocg/features/descriptor.h"
#include "ocg/features/feature_grid.h"
#include "ocg/features/orb_options.h"
#include "ocg/features/scale_pyramid.h"

namespace cv {
class ORB;
}

namespace ocg {

// What one image gives: keypoints in the distorted image (level-0 pixels; angle in
// degrees, octave = pyramid level, size = 31 * scale, response = FAST score), their
// undistorted positions, descriptors and a grid over the undistorted positions.
struct ExtractedFeatures {
  std::vector<cv::KeyPoint> keypoints;
  std::vector<Eigen::Vector2d> undistorted;
  std::vector<Descriptor> descriptors;
  FeatureGrid grid;

  std::size_t size() const { return keypoints.size(); }
  std::vector<int> Levels() const;
};

// Not thread-safe: Extract reuses the pyramid buffers. Use one extractor per thread.
class OrbExtractor {
 public:
  // Throws OptionError (naming the ORBextractor.* key) for impossible options.
  explicit OrbExtractor(const OrbExtractorOptions& options);
  ~OrbExtractor();
  OrbExtractor(const OrbExtractor&) = delete;
  OrbExtractor& operator=(const OrbExtractor&) = delete;

  // image: 8-bit grayscale or BGR (converted). Throws std::invalid_argument for an empty
  // image or one whose size differs from the camera's.
  ExtractedFeatures Extract(const cv::Mat& image, const PinholeCamera& camera);

  // Keypoints and descriptors only (no undistortion, no grid): for vocabulary training.
  void Detect(const cv::Mat& gray, std::vector<cv::KeyPoint>* keypoints,
              std::vector<Descriptor>* descriptors);

  const ScalePyramid& pyramid() const { return pyramid_; }
  const OrbExtractorOptions& options() const { return options_; }
  // Keypoints wanted on each level: geometric in the level's scale, summing to features.
  const std::vector<int>& FeaturesPerLevel() const { return features_per_level_; }

 private:
  void BuildPyramid(const cv::Mat& gray);
  void DetectLevel(int level, int wanted, std::vector<cv::KeyPoint>* keypoints) const;

  OrbExtractorOptions options_;
  ScalePyramid pyramid_;
  std::vector<int> features_per_level_;
  std::vector<int> circle_half_width_;  // per row offset of the orientation patch
  std::vector<cv::Mat> levels_;
  cv::Ptr<cv::ORB> describer_;
};

// The quadtree distribution on its own (exposed for tests): keeps at most wanted of the
// candidates, the strongest in each node after splitting the most crowded node until
// there are wanted nodes, in the rectangle [min, max). Returns indices into candidates.
std::vector<int> DistributeByQuadtree(const std::vector<cv::KeyPoint>& candidates,
                                      const cv::Point2f& min, const cv::Point2f& max, int wanted);

// Level l of the pyramid of an image: the image shrunk to lround(size / scale[l]) pixels.
std::vector<cv::Size> PyramidLevelSizes(const cv::Size& image, const ScalePyramid& pyramid);

// Where DetectLevel looks for FAST corners on one pyramid level (exposed for tests):
// region is the level less a 16-pixel border (level pixels), split into cells of about
// 30 x 30 pixels that tile it exactly; a cell where the strict threshold finds no corner
// is searched again with the lenient one.
struct FastCellLayout {
  cv::Rect region;
  CellSplit columns;  // over region.width
  CellSplit rows;     // over region.height
  // Cell (column, row) in region pixels.
  cv::Rect Cell(int column, int row) const;
};
// std::nullopt for a level too small to hold a corner.
std::optional<FastCellLayout> FastCells(const cv::Size& level_size);

// Intensity-centroid angle in degrees of the patch of radius 15 around (x, y).
float IntensityCentroidAngle(const cv::Mat& gray, const cv::Point2f& point,
                             const std::vector<int>& circle_half_width);
std::vector<int> CircleHalfWidths(int radius);

}  // namespace ocg
