// ocg_eval: trajectory metrics (ATE, RPE) the way TUM's scripts and evo compute them, and
// the object-map metrics of the paper's Table I (SPEC 4).

#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

#include "ate_plot.h"
#include "cli_common.h"

#include "ocg/eval/object_metrics.h"
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

// The options ate and rpe share.
struct TrajectoryPair {
  std::string gt, est, times, align = "sim3";
  double max_dt = 0.02;
  bool json = false;
};

void AddTrajectoryPairOptions(CLI::App* command, TrajectoryPair* pair,
                              const std::string& align_help) {
  command->add_option("--gt", pair->gt, "ground-truth trajectory (TUM or KITTI format)")
      ->required()
      ->check(CLI::ExistingFile);
  command->add_option("--est", pair->est, "estimated trajectory (TUM or KITTI format)")
      ->required()
      ->check(CLI::ExistingFile);
  command
      ->add_option("--times", pair->times,
                   "KITTI times.txt: the times of a KITTI file's rows, needed when only one "
                   "of the two files is KITTI (two KITTI files pair row by row)")
      ->check(CLI::ExistingFile);
  command->add_option("--align", pair->align, align_help)
      ->capture_default_str()
      ->check(CLI::IsMember({"sim3", "se3", "none"}));
  command->add_option("--max-dt", pair->max_dt, "largest timestamp difference of a pair, seconds")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  command->add_flag("--json", pair->json, "print JSON instead of text");
}

// Both files, each in its format (TUM or KITTI, by content). Two KITTI files pair row by
// row (evo_ape kitti) and must hold as many poses; a KITTI file beside a TUM one needs the
// times of its rows.
std::pair<std::vector<ocg::StampedPose>, std::vector<ocg::StampedPose>> ReadPair(
    const TrajectoryPair& pair) {
  const bool gt_kitti = ocg::DetectTrajectoryFormat(pair.gt) == ocg::TrajectoryFormat::kKitti;
  const bool est_kitti = ocg::DetectTrajectoryFormat(pair.est) == ocg::TrajectoryFormat::kKitti;
  if (gt_kitti != est_kitti && pair.times.empty()) {
    throw std::invalid_argument(
        "'" + (gt_kitti ? pair.gt : pair.est) + "' holds KITTI poses (no times) and '" +
        (gt_kitti ? pair.est : pair.gt) +
        "' TUM poses: give the KITTI rows' times with --times (the sequence's times.txt)");
  }
  const std::string times = gt_kitti && est_kitti ? "" : pair.times;
  auto poses = std::make_pair(ocg::ReadTrajectory(pair.gt, gt_kitti ? times : ""),
                              ocg::ReadTrajectory(pair.est, est_kitti ? times : ""));
  if (gt_kitti && est_kitti && poses.first.size() != poses.second.size()) {
    throw std::invalid_argument("two KITTI files pair row by row, but '" + pair.gt + "' holds " +
                                std::to_string(poses.first.size()) + " poses and '" + pair.est +
                                "' " + std::to_string(poses.second.size()));
  }
  return poses;
}

struct ConvertInput {
  std::string input, output, to, times;
};

// TUM to KITTI (one row per pose, or with --times one row per frame of times.txt, the pose
// at its time) and KITTI to TUM (with --times: the rows' times).
void Convert(const ConvertInput& input) {
  const bool kitti_in = ocg::DetectTrajectoryFormat(input.input) == ocg::TrajectoryFormat::kKitti;
  if (input.to == "tum") {
    if (kitti_in && input.times.empty()) {
      throw std::invalid_argument("'" + input.input +
                                  "' holds KITTI poses, which have no times: give them with "
                                  "--times (the sequence's times.txt)");
    }
    const std::vector<ocg::StampedPose> poses = ocg::ReadTrajectory(input.input, input.times);
    ocg::WriteTumTrajectory(input.output, poses);
    std::printf("wrote %zu poses to %s (TUM)\n", poses.size(), input.output.c_str());
    return;
  }
  const std::vector<ocg::StampedPose> poses = ocg::ReadTrajectory(input.input);
  std::vector<ocg::StampedPose> rows;
  if (input.times.empty() || kitti_in) {
    rows = poses;
  } else {
    // One row per frame, as KITTI's ground truth: a frame without a pose (before
    // initialization, lost) leaves no row to give, so the file would pair wrongly.
    const ocg::KittiTimes times = ocg::ReadKittiTimes(input.times);
    std::size_t missing = 0;
    std::string first_missing;
    for (std::size_t i = 0; i < times.seconds.size(); ++i) {
      const std::optional<ocg::SE3> T_cw = ocg::PoseAtTime(poses, times.seconds[i], 0.0, 1e-6);
      if (!T_cw) {
        if (missing++ == 0)
          first_missing = times.texts[i] + " (line " + std::to_string(i + 1) + ")";
        continue;
      }
      rows.push_back({times.seconds[i], times.texts[i], T_cw->Inverse()});
    }
    if (missing > 0) {
      throw std::invalid_argument(
          std::to_string(missing) + " of the " + std::to_string(times.seconds.size()) +
          " frames of '" + input.times + "' have no pose in '" + input.input +
          "' (first: " + first_missing +
          "): KITTI rows are one per frame; compare the TUM file instead (evo_ape tum, "
          "ocg_eval ate), or leave out --times for one row per pose");
    }
  }
  ocg::WriteKittiTrajectory(input.output, rows);
  std::printf("wrote %zu poses to %s (KITTI)\n", rows.size(), input.output.c_str());
}

struct ObjectsInput {
  std::string gt, run, groundtruth;
  ocg::ObjectMatchOptions match;
  bool json = false;
};

void EvaluateObjects(const ObjectsInput& input) {
  std::optional<ocg::RunAlignment> aligned;
  const ocg::ObjectMetrics m =
      ocg::EvaluateRunObjects(input.gt, input.run, input.groundtruth, input.match, &aligned);
  nlohmann::json alignment = nullptr;
  if (aligned) {
    alignment = {{"trajectory", aligned->trajectory},
                 {"pairs", aligned->pairs},
                 {"scale", aligned->scale},
                 {"ate_rmse", aligned->ate_rmse}};
  }
  if (input.json) {
    std::cout << nlohmann::json({{"corr_s", m.corr_s},
                                 {"unident_s", m.unident_s},
                                 {"redun_s", m.redun_s},
                                 {"redun_duplicates", m.redun_duplicates},
                                 {"redun_spurious", m.redun_spurious},
                                 {"corr_m", m.corr_m},
                                 {"delet_s", m.delet_s},
                                 {"unident_m", m.unident_m},
                                 {"acc", m.acc},
                                 {"prec", m.prec},
                                 {"recall", m.recall},
                                 {"gt_static", m.gt_static},
                                 {"gt_outdated", m.gt_outdated},
                                 {"gt_never_in_view", m.gt_never_in_view},
                                 {"never_in_view_ids", m.never_in_view_ids},
                                 {"never_in_view_object_ids", m.never_in_view_object_ids},
                                 {"live_objects", m.live_objects},
                                 {"removed_objects", m.removed_objects},
                                 {"gt_moves", m.gt_moves},
                                 {"moves_right", m.moves_right},
                                 {"deleted_static_ids", m.deleted_static_ids},
                                 {"unidentified_static_ids", m.unidentified_static_ids},
                                 {"unidentified_moved_ids", m.unidentified_moved_ids},
                                 {"duplicate_ids", m.duplicate_ids},
                                 {"spurious_ids", m.spurious_ids},
                                 {"alignment", alignment}})
                     .dump(1)
              << "\n";
    return;
  }
  std::printf(
      "| Corr.S | Unident.S | Redun.S (dup+spur) | Corr.M | Delet.S | Unident.M | Acc | "
      "Prec | Recall |\n|---|---|---|---|---|---|---|---|---|\n");
  std::printf("| %d | %d | %d (%d+%d) | %d | %d | %d | %.3f | %.3f | %.3f |\n", m.corr_s,
              m.unident_s, m.redun_s, m.redun_duplicates, m.redun_spurious, m.corr_m, m.delet_s,
              m.unident_m, m.acc, m.prec, m.recall);
  std::printf("| GT: %d static | | | %d moved | | | | | |\n", m.gt_static, m.gt_outdated);
  if (m.gt_never_in_view > 0) {
    std::printf("%d static object(s) never in view left out of the ground truth (ids",
                m.gt_never_in_view);
    for (const int id : m.never_in_view_ids) std::printf(" %d", id);
    std::printf("; --include-never-in-view counts them)");
    if (!m.never_in_view_object_ids.empty()) {
      std::printf("; live objects at their places, ignored:");
      for (const long long id : m.never_in_view_object_ids) std::printf(" %lld", id);
    }
    std::printf("\n");
  }
  std::printf("%d live objects, %d removed by change detection", m.live_objects, m.removed_objects);
  if (m.gt_moves > 0) {
    std::printf("; moves reported right: %d of %d", m.moves_right, m.gt_moves);
  }
  if (!alignment.is_null()) {
    std::printf("; run aligned to ground truth (Sim(3), scale %.4f, ATE %.4f m)",
                alignment["scale"].get<double>(), alignment["ate_rmse"].get<double>());
  }
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "ocg_eval: trajectory error metrics (TUM or KITTI format files, camera-to-world "
      "poses)",
      "ocg_eval"};
  app.require_subcommand(1);
  std::string log_level;
  ocg::tools::AddLogLevelOption(app, &log_level);

  TrajectoryPair ate_input, rpe_input;
  CLI::App* ate = app.add_subcommand("ate", "absolute trajectory error of the positions");
  AddTrajectoryPairOptions(ate, &ate_input, "alignment: sim3 (monocular), se3 or none");
  CLI::App* rpe = app.add_subcommand("rpe", "relative pose error over a fixed delta");
  AddTrajectoryPairOptions(rpe, &rpe_input, "scale from: sim3 (monocular), se3 or none");
  double rpe_delta = 1.0;
  std::string rpe_unit = "frames";
  rpe->add_option("--delta", rpe_delta, "distance between the two poses")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  rpe->add_option("--delta-unit", rpe_unit, "frames (associated poses) or seconds")
      ->capture_default_str()
      ->check(CLI::IsMember({"frames", "seconds"}));

  std::string ate_plot;
  ate->add_option("--plot", ate_plot,
                  "also draw the aligned trajectories (top view) and the per-axis error over "
                  "time into this PNG (matplotlib: python3-matplotlib)");

  ConvertInput convert_input;
  CLI::App* convert = app.add_subcommand(
      "convert", "write a trajectory in the other format: TUM to KITTI poses, KITTI to TUM");
  convert->add_option("--in", convert_input.input, "trajectory (TUM or KITTI, by content)")
      ->required()
      ->check(CLI::ExistingFile);
  convert->add_option("--out", convert_input.output, "file to write")->required();
  convert->add_option("--to", convert_input.to, "kitti or tum")
      ->required()
      ->check(CLI::IsMember({"kitti", "tum"}));
  convert
      ->add_option("--times", convert_input.times,
                   "the sequence's KITTI times.txt: to kitti, one row per frame (the pose at "
                   "its time; every frame needs one); to tum, the KITTI rows' times")
      ->check(CLI::ExistingFile);

  ObjectsInput objects_input;
  CLI::App* objects = app.add_subcommand(
      "objects", "object-map metrics of the paper's Table I (SPEC 4) for a run folder");
  objects->add_option("--gt", objects_input.gt, "ground-truth objects (objects_gt.json)")
      ->required()
      ->check(CLI::ExistingFile);
  objects->add_option("--run", objects_input.run, "run folder (objects.json, changes.json)")
      ->required()
      ->check(CLI::ExistingDirectory);
  objects
      ->add_option("--groundtruth", objects_input.groundtruth,
                   "ground-truth trajectory: align the run's trajectory to it (Sim(3)) first; "
                   "leave out for runs on ground-truth poses")
      ->check(CLI::ExistingFile);
  objects
      ->add_option("--distance-factor", objects_input.match.distance_factor,
                   "match within this share of the larger ground-truth extent")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  objects
      ->add_option("--min-distance", objects_input.match.min_distance,
                   "but never closer than this, metres")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  objects->add_flag("--include-never-in-view", objects_input.match.include_never_in_view,
                    "count static objects the sequence never shows (objects_gt.json's "
                    "\"frames_in_view\": 0) as ground truth too; by default they are left out, "
                    "as a list made from the frames would not hold them");
  objects->add_flag("--json", objects_input.json, "print JSON instead of a table row");

  return ocg::tools::RunTool(app, argc, argv, log_level, [&] {
    if (objects->parsed()) {
      EvaluateObjects(objects_input);
      return;
    }
    if (convert->parsed()) {
      Convert(convert_input);
      return;
    }
    if (ate->parsed()) {
      ocg::AteOptions options;
      options.alignment = ocg::ParseAlignmentMode(ate_input.align);
      options.max_dt = ate_input.max_dt;
      const auto [reference, estimate] = ReadPair(ate_input);
      const ocg::AteResult result = ocg::ComputeAte(reference, estimate, options);
      // The plot first: when it cannot be drawn the run fails before printing a result.
      if (!ate_plot.empty()) {
        ocg::tools::PlotAte(reference, estimate, result, ate_input.align, ate_plot);
      }
      if (ate_input.json) {
        nlohmann::json json = StatisticsJson(result.translation);
        json["pairs"] = result.pairs.size();
        json["scale"] = result.reference_from_estimate.scale();
        json["alignment"] = ate_input.align;
        std::cout << json.dump(1) << "\n";
        return;
      }
      std::printf("ATE (translation), alignment %s\npairs   %zu\nscale   %.6f\n",
                  ate_input.align.c_str(), result.pairs.size(),
                  result.reference_from_estimate.scale());
      PrintStatistics(result.translation, "m");
    } else {
      ocg::RpeOptions options;
      options.alignment = ocg::ParseAlignmentMode(rpe_input.align);
      options.max_dt = rpe_input.max_dt;
      options.delta = rpe_delta;
      options.delta_in_seconds = rpe_unit == "seconds";
      const auto [reference, estimate] = ReadPair(rpe_input);
      const ocg::RpeResult result = ocg::ComputeRpe(reference, estimate, options);
      if (rpe_input.json) {
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
          rpe_delta, rpe_unit.c_str(), rpe_input.align.c_str(), result.associated, result.scale,
          result.translation.count);
      PrintStatistics(result.translation, "m");
      std::printf("-- rotation\n");
      PrintStatistics(result.rotation_deg, "deg");
    }
  });
}
