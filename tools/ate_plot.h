#pragma once
// ocg_eval ate --plot: the aligned trajectories drawn by matplotlib. ocg_eval computes
// every number (association, alignment, errors) and hands them to ocg_plot_ate.py, the
// script installed beside it, so the picture shows exactly what ocg_eval printed and the
// C++ tool needs no drawing code of its own.

#include <string>
#include <vector>

#include "ocg/eval/trajectory_error.h"
#include "ocg/io/trajectory.h"

namespace ocg::tools {

// Writes png_path (PNG, 1200 x 700 pixels): the top view of the ground truth and of the
// estimate aligned to it (the two world axes of largest extent), and the per-axis error
// (estimate - ground truth, metres, ground-truth frame) of each pair over time. The script
// is looked up beside the running executable.
// Throws std::runtime_error naming the interpreter and the script when Python, the script
// or matplotlib is missing (install python3-matplotlib) or the plot fails; nothing is
// left at png_path then.
void PlotAte(const std::vector<StampedPose>& reference, const std::vector<StampedPose>& estimate,
             const AteResult& result, const std::string& alignment, const std::string& png_path);

}  // namespace ocg::tools
