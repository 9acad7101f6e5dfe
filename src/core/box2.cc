#include "ocg/core/box2.h"

#include <algorithm>

namespace ocg {

double SharedArea(const Box2& a, const Box2& b) {
  return Box2{std::max(a.x0, b.x0), std::max(a.y0, b.y0), std::min(a.x1, b.x1),
              std::min(a.y1, b.y1)}
      .Area();
}

double IntersectionOverUnion(const Box2& a, const Box2& b) {
  const double intersection = SharedArea(a, b);
  const double united = a.Area() + b.Area() - intersection;
  return united > 0 ? intersection / united : 0.0;
}

}  // namespace ocg
