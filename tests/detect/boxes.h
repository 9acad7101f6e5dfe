#pragma once
// Boxes for the detector tests.

#include "ocg/io/detections.h"

namespace ocg::testing {

inline Detection Box(int class_id, double x, double y, double w, double h, double confidence) {
  Detection d;
  d.class_id = class_id;
  d.x = x;
  d.y = y;
  d.width = w;
  d.height = h;
  d.confidence = confidence;
  return d;
}

}  // namespace ocg::testing
