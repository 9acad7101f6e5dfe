#pragma once
// An object's colour inside its detection boxes (docs/sessions.md, "Moves in changes.json").
// Flat objects (remotes, cell phones) seen from a person's height fill a box of a few
// tens of pixels at a grazing angle: ORB's patches there are the table and the object's
// edge, and their box appearance (box_appearance.h) finds nothing of them. Their colour
// is still there, and goes with the object when it is carried elsewhere.
//
// The table around the object is in the box too, and does not move with it; after two
// objects of one class swap places, each box holds the other's old table. A box's central
// part holds more of the object than its border ring (the corners of an axis-aligned box
// are mostly background), so the colours the centre has more of than the ring are the
// object's: the signature is the positive part of (centre histogram - ring histogram),
// normalized. The background's colours, in centre and ring alike, cancel.
//
// Colours are binned by hue and saturation (which shading and exposure barely change)
// where a pixel has colour, and by value where it is grey.

#include <array>
#include <optional>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "ocg/objects/box.h"

namespace ocg {

inline constexpr int kHueBins = 12;
inline constexpr int kSaturationBins = 2;
inline constexpr int kGreyBins = 4;
inline constexpr int kColourBins = kHueBins * kSaturationBins + kGreyBins;

// Shares of the object's colour per bin, summing to 1.
using ColourHistogram = std::array<float, kColourBins>;

struct ColourSignatureOptions {
  // Share of the box's width and height that is its centre; the rest is the ring.
  double centre_share = 0.6;
  // A pixel is grey below this saturation or value (0-1).
  double min_saturation = 0.2;
  double min_value = 0.15;
  // Boxes smaller than this in either direction (pixels, inside the image) give none.
  int min_box_side = 6;
  // Mass the centre must have beyond the ring (of 1) for the box to give a signature: a
  // box whose centre looks like its ring shows no object colour of its own.
  double min_object_mass = 0.05;
  // Throws std::invalid_argument naming the field.
  void Check() const;
};

// The signature of the object in box (pixels) of a BGR 8-bit image; none when the box,
// clipped to the image, is too small or its centre has no colour its ring lacks.
// Throws std::invalid_argument when the image is not CV_8UC3.
std::optional<ColourHistogram> BoxColourSignature(const cv::Mat& bgr, const Box2& box,
                                                  const ColourSignatureOptions& options);

// The mean of signatures, normalized (none for an empty list).
std::optional<ColourHistogram> MeanColour(const std::vector<ColourHistogram>& signatures);

// Histogram intersection of two signatures: 1 for the same colours, 0 for none shared.
double ColourSimilarity(const ColourHistogram& a, const ColourHistogram& b);

}  // namespace ocg
