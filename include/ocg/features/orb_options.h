#pragma once
// ORB extractor options: ORB-SLAM2's ORBextractor.* keys, same meaning and defaults.

#include "ocg/core/option_fields.h"

namespace ocg {

class SettingsFile;

struct OrbExtractorOptions {
  int features = 1000;              // ORBextractor.nFeatures: keypoints per image
  double scale_factor = 1.2;        // ORBextractor.scaleFactor: between pyramid levels
  int levels = 8;                   // ORBextractor.nLevels: pyramid levels
  int initial_fast_threshold = 20;  // ORBextractor.iniThFAST: FAST threshold tried first per cell
  int minimum_fast_threshold = 7;   // ORBextractor.minThFAST: fallback for low-contrast cells

  // The settings keys, once (ocg/core/option_fields.h).
  template <typename Self, typename Visitor>
  static void VisitFields(Self& self, Visitor&& visit) {
    visit("ORBextractor.nFeatures", self.features, OptionBound::AtLeast(1), "keypoints per image");
    visit("ORBextractor.scaleFactor", self.scale_factor, OptionBound::MoreThan(1),
          "scale between pyramid levels");
    visit("ORBextractor.nLevels", self.levels, OptionBound::Closed(1, 32), "pyramid levels");
    visit("ORBextractor.iniThFAST", self.initial_fast_threshold, OptionBound::Closed(1, 255),
          "FAST threshold tried first in each cell");
    visit("ORBextractor.minThFAST", self.minimum_fast_threshold, OptionBound::Closed(1, 255),
          "FAST threshold for cells where the first finds nothing (at most `iniThFAST`)");
  }
  void Check() const;  // throws OptionError naming the key
};

void ReadSettings(const SettingsFile& file, OrbExtractorOptions* options);

}  // namespace ocg
