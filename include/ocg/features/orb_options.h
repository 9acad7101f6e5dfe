#pragma once
// ORB extractor options: ORB-SLAM2's ORBextractor.* keys, same meaning and defaults.

namespace ocg {

class SettingsFile;

struct OrbExtractorOptions {
  int features = 1000;              // ORBextractor.nFeatures: keypoints per image
  double scale_factor = 1.2;        // ORBextractor.scaleFactor: between pyramid levels
  int levels = 8;                   // ORBextractor.nLevels: pyramid levels
  int initial_fast_threshold = 20;  // ORBextractor.iniThFAST: FAST threshold tried first per cell
  int minimum_fast_threshold = 7;   // ORBextractor.minThFAST: fallback for low-contrast cells

  void Check() const;  // throws OptionError naming the key
};

void ReadSettings(const SettingsFile& file, OrbExtractorOptions* options);

}  // namespace ocg
