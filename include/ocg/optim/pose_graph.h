#pragma once
// Sim(3) pose graph optimization (loop closing's essential graph): keyframe poses with
// scale, relative-similarity edges (spanning tree, strong covisibility, loops), solved
// with Ceres. Plain data in, plain data out, as bundle_adjustment.h.

#include <string>
#include <vector>

#include "ocg/core/lie.h"

namespace ocg {

struct PoseGraphEdge {
  int i = 0;
  int j = 0;
  Sim3 S_ij;            // measured S_iw * S_jw^-1: camera j's frame into camera i's
  double weight = 1.0;  // scales the edge's information
};

struct PoseGraphProblem {
  std::vector<Sim3> poses;  // S_iw: world into camera i, the scale of the map there
  std::vector<bool> fixed;  // same size as poses (the loop keyframe, the first one)
  std::vector<PoseGraphEdge> edges;
};

struct PoseGraphOptions {
  int max_iterations = 20;
};

struct PoseGraphReport {
  bool solved = false;
  std::string message;
  int iterations = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
};

// Optimizes the free poses in place. The residual of an edge is the rotation vector, the
// translation and the log scale of S_ij * S_jw * S_iw^-1 (identity when the poses agree
// with the measurement). Single-threaded: runs repeat exactly. Throws
// std::invalid_argument for an edge naming a missing pose.
PoseGraphReport OptimizePoseGraph(PoseGraphProblem* problem, const PoseGraphOptions& options);

}  // namespace ocg
