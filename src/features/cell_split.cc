#include "ocg/features/cell_split.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace ocg {

CellSplit SplitIntoCells(int length, double nominal_size) {
  if (length <= 0 || !(nominal_size > 0.0)) {
    throw std::invalid_argument("SplitIntoCells: length " + std::to_string(length) +
                                " and cell size " + std::to_string(nominal_size) +
                                " must be positive");
  }
  CellSplit split;
  split.length = length;
  // Clamped as a double first: a tiny nominal size must not overflow the int.
  const double cells = std::min(static_cast<double>(length), length / nominal_size);
  split.count = std::max(1, static_cast<int>(cells));
  return split;
}

}  // namespace ocg
