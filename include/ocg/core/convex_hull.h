#pragma once
// Convex hulls of 2-D points (image pixels, ground-plane coordinates).

#include <vector>

#include <Eigen/Core>

namespace ocg {

// z of (b - a) x (c - a): positive when a, b, c turn counter-clockwise.
double Turn(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c);

// The convex hull, counter-clockwise from the lowest-x point, without collinear or repeated
// points (Andrew's monotone chain, O(n log n)). Fewer than 3 points come back sorted as
// they are; all points on one line give the two ends.
std::vector<Eigen::Vector2d> ConvexHull(std::vector<Eigen::Vector2d> points);

}  // namespace ocg
