#pragma once
// Splitting a run of pixels (an image's width or height, a pyramid level's detection
// region) into cells of about a nominal size, for the grids laid over images.
//
// Dividing the length into floor(length / nominal) cells and rounding the cell size up
// lets the last cells start past the end (a 1888-pixel region in 62 cells of 31 pixels:
// the 62nd starts at 1891). Here the cell boundaries are floor(i * length / count), so the
// cells tile [0, length) exactly, none is empty and their sizes differ by at most one pixel.

namespace ocg {

struct CellSplit {
  int length = 0;  // pixels split, > 0
  int count = 0;   // cells, in [1, length]

  // First pixel of cell i in [0, count]; Start(count) == length.
  int Start(int i) const { return static_cast<int>(static_cast<long long>(i) * length / count); }
  // Pixels in cell i: floor(length / count) or one more.
  int Size(int i) const { return Start(i + 1) - Start(i); }
  // The cell holding pixel x in [0, length): the i with Start(i) <= x < Start(i + 1).
  int CellOf(int x) const {
    return static_cast<int>(((static_cast<long long>(x) + 1) * count - 1) / length);
  }
};

// floor(length / nominal_size) cells (at least one): no cell is smaller than nominal_size
// unless length is. Throws std::invalid_argument unless length > 0 and nominal_size > 0.
CellSplit SplitIntoCells(int length, double nominal_size);

}  // namespace ocg
