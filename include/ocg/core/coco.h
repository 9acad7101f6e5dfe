#pragma once
// The COCO-80 class list that YOLO detectors (and the EAO detection format) index.

#include <string>

namespace ocg {

constexpr int kCocoClassCount = 80;
// Name of a COCO-80 index ("cup" for 41); "unknown" outside [0, 79].
std::string CocoClassName(int class_id);
// Index of a name, -1 when not a COCO-80 class.
int CocoClassId(const std::string& name);

}  // namespace ocg
