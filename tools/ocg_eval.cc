// ocg_eval: trajectory metrics (ATE, RPE) the way TUM's scripts and evo compute them.

#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli_common.h"
#include "ocg/eval/trajectory_error.h"
#include "ocg/io/trajectory.h"

namespace {

nlohmann::json StatisticsJson(const ocg::ErrorStatistics& stats) {
  return {{"count", stats.count},   {"rmse", stats.rmse}, {"mean", stats.mean},
          {"median", stats.median}, {"std", stats.std},   {"min", stats.min},
          {"max", stats.max}};
}

void PrintStatistics(const ocg::ErrorStatistics& stats, const char* unit) {
  std::printf(
      "rmse    %.6f %s\nmean    %.6f %s\nmedian  %.6f %s\nstd     %.6f %s\n"
      "min     %.6f %s\nmax     %.6f %s\n",
      stats.rmse, unit, stats.mean, unit, stats.median, unit, stats.std, unit, stats.min, unit,
      stats.max, unit);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ocg_eval: trajectory error metrics (TUM format files, camera-to-world poses)",
               "ocg_eval"};
  app.require_subcommand(1);
  std::string log_level;
  ocg::tools::AddLogLevelOption(app, &log_level);

  std::string ate_gt, ate_est, ate_align = "sim3";
  double ate_max_dt = 0.02;
  bool ate_json = false;
  CLI::App* ate = app.add_subcommand("ate", "absolute trajectory error of the positions");
  ate->add_option("--gt", ate_gt, "ground-truth trajectory (TUM format)")
      ->required()
      ->check(CLI::ExistingFile);
  ate->add_option("--est", ate_est, "estimated trajectory (TUM format)")
      ->required()
      ->check(CLI::ExistingFile);
  ate->add_option("--align", ate_align, "alignment: sim3 (monocular), se3 or none")
      ->capture_default_str()
      ->check(CLI::IsMember({"sim3", "se3", "none"}));
  ate->add_option("--max-dt", ate_max_dt, "largest timestamp difference of a pair, seconds")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  ate->add_flag("--json", ate_json, "print JSON instead of text");

  std::string rpe_gt, rpe_est, rpe_align = "sim3", rpe_unit = "frames";
  double rpe_max_dt = 0.02, rpe_delta = 1.0;
  bool rpe_json = false;
  CLI::App* rpe = app.add_subcommand("rpe", "relative pose error over a fixed delta");
  rpe->add_option("--gt", rpe_gt, "ground-truth trajectory (TUM format)")
      ->required()
      ->check(CLI::ExistingFile);
  rpe->add_option("--est", rpe_est, "estimated trajectory (TUM format)")
      ->required()
      ->check(CLI::ExistingFile);
  rpe->add_option("--align", rpe_align, "scale from: sim3 (monocular), se3 or none")
      ->capture_default_str()
      ->check(CLI::IsMember({"sim3", "se3", "none"}));
  rpe->add_option("--max-dt", rpe_max_dt, "largest timestamp difference of a pair, seconds")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  rpe->add_option("--delta", rpe_delta, "distance between the two poses")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  rpe->add_option("--delta-unit", rpe_unit, "frames (associated poses) or seconds")
      ->capture_default_str()
      ->check(CLI::IsMember({"frames", "seconds"}));
  rpe->add_flag("--json", rpe_json, "print JSON instead of text");

  return ocg::tools::RunTool(app, argc, argv, log_level, [&] {
    if (ate->parsed()) {
      ocg::AteOptions options;
      options.alignment = ocg::ParseAlignmentMode(ate_align);
      options.max_dt = ate_max_dt;
      const ocg::AteResult result =
          ocg::ComputeAte(ocg::ReadTumTrajectory(ate_gt), ocg::ReadTumTrajectory(ate_est), options);
      if (ate_json) {
        nlohmann::json json = StatisticsJson(result.translation);
        json["pairs"] = result.pairs.size();
        json["scale"] = result.reference_from_estimate.scale();
        json["alignment"] = ate_align;
        std::cout << json.dump(1) << "\n";
        return;
      }
      std::printf("ATE (translation), alignment %s\npairs   %zu\nscale   %.6f\n", ate_align.c_str(),
                  result.pairs.size(), result.reference_from_estimate.scale());
      PrintStatistics(result.translation, "m");
    } else {
      ocg::RpeOptions options;
      options.alignment = ocg::ParseAlignmentMode(rpe_align);
      options.max_dt = rpe_max_dt;
      options.delta = rpe_delta;
      options.delta_in_seconds = rpe_unit == "seconds";
      const ocg::RpeResult result =
          ocg::ComputeRpe(ocg::ReadTumTrajectory(rpe_gt), ocg::ReadTumTrajectory(rpe_est), options);
      if (rpe_json) {
        std::cout << nlohmann::json({{"pairs", result.associated},
                                     {"scale", result.scale},
                                     {"translation", StatisticsJson(result.translation)},
                                     {"rotation_deg", StatisticsJson(result.rotation_deg)}})
                         .dump(1)
                  << "\n";
        return;
      }
      std::printf(
          "RPE, delta %g %s, scale from %s\npairs   %zu\nscale   %.6f\nrelative motions %zu\n"
          "-- translation\n",
          rpe_delta, rpe_unit.c_str(), rpe_align.c_str(), result.associated, result.scale,
          result.translation.count);
      PrintStatistics(result.translation, "m");
      std::printf("-- rotation\n");
      PrintStatistics(result.rotation_deg, "deg");
    }
  });
}
