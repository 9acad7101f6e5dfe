#pragma once
// Axis-aligned image rectangles and their overlap: shared by the object layer (detections
// against projected cuboids) and the detector (non-maximum suppression).

#include <Eigen/Core>

namespace ocg {

// Axis-aligned image rectangle, pixels, min corner inclusive.
struct Box2 {
  double x0 = 0.0, y0 = 0.0, x1 = 0.0, y1 = 0.0;

  double Width() const { return x1 - x0; }
  double Height() const { return y1 - y0; }
  double Area() const { return Width() > 0 && Height() > 0 ? Width() * Height() : 0.0; }
  Eigen::Vector2d Centre() const { return {0.5 * (x0 + x1), 0.5 * (y0 + y1)}; }
};

// The area two boxes share (0 when apart), pixels squared.
double SharedArea(const Box2& a, const Box2& b);

// Intersection over union in [0, 1]; 0 when both boxes are empty.
double IntersectionOverUnion(const Box2& a, const Box2& b);

}  // namespace ocg
