#include "ocg/objects/objects_options.h"

#include <algorithm>
#include <cmath>

#include "ocg/core/options.h"
#include "ocg/core/settings_file.h"

namespace ocg {

bool ObjectsOptions::MapsClass(int class_id) const {
  if (classes.empty()) return class_id != 0;
  return std::find(classes.begin(), classes.end(), class_id) != classes.end();
}

void ObjectsOptions::Check() const {
  for (int class_id : classes) {
    RequireOption(class_id >= 0 && class_id < 80, "Objects.classes",
                  "COCO-80 class ids are 0 to 79, got " + std::to_string(class_id));
  }
  RequireOption(min_confidence >= 0 && min_confidence <= 1, "Objects.min_confidence",
                "must be in [0, 1]");
  RequireOption(border_margin >= 0, "Objects.border_margin", "must be non-negative");
  RequireOption(min_association_score > 0 && min_association_score <= 1,
                "Objects.min_association_score", "must be in (0, 1]");
  RequireOption(nms_iou > 0 && nms_iou <= 1, "Objects.nms_iou", "must be in (0, 1]");
  RequireOption(min_reacquire_iou >= 0 && min_reacquire_iou <= 1, "Objects.min_reacquire_iou",
                "must be in [0, 1]");
  RequireOption(max_ray_distance > 0, "Objects.max_ray_distance", "must be positive");
  RequireOption(predicted_box_frames >= 0, "Objects.predicted_box_frames", "must be non-negative");
  RequireOption(candidate_min_observations >= 2, "Objects.candidate_min_observations",
                "must be at least 2 (a centre needs two rays)");
  RequireOption(candidate_min_parallax_deg >= 0 && candidate_min_parallax_deg < 90,
                "Objects.candidate_min_parallax_deg", "must be in [0, 90)");
  RequireOption(candidate_max_missed_frames >= 1, "Objects.candidate_max_missed_frames",
                "must be at least 1");
  RequireOption(candidate_gap_seconds >= 0 && std::isfinite(candidate_gap_seconds),
                "Objects.candidate_gap_seconds", "must be a non-negative number of seconds");
  RequireOption(min_inlier_share > 0 && min_inlier_share <= 1, "Objects.min_inlier_share",
                "must be in (0, 1]");
  RequireOption(min_sightings >= 0, "Objects.min_sightings", "must be non-negative");
  RequireOption(probation_keyframes >= 0, "Objects.probation_keyframes", "must be non-negative");
  RequireOption(max_rays >= candidate_min_observations, "Objects.max_rays",
                "must be at least Objects.candidate_min_observations");
  RequireOption(max_sightings == 0 || max_sightings >= std::max(8, max_rays),
                "Objects.max_sightings", "must be 0 (keep all) or at least Objects.max_rays and 8");
  RequireOption(merge_distance >= 0, "Objects.merge_distance", "must be non-negative");
  RequireOption(merge_overlap > 0 && merge_overlap <= 1, "Objects.merge_overlap",
                "must be in (0, 1]");
  RequireOption(duplicate_box_iou > 0 && duplicate_box_iou <= 1, "Objects.duplicate_box_iou",
                "must be in (0, 1]");
  RequireOption(restore_window >= 0, "Objects.restore_window", "must be non-negative (seconds)");
  RequireOption(restore_overlap > 0 && restore_overlap <= 1, "Objects.restore_overlap",
                "must be in (0, 1]");
  RequireOption(up.allFinite() && up.norm() > 1e-9, "Objects.up", "must be a non-zero vector");
  RequireOption(point_box_shrink >= 0 && point_box_shrink < 0.5, "Objects.point_box_shrink",
                "must be in [0, 0.5)");
  RequireOption(min_point_votes >= 1, "Objects.min_point_votes", "must be at least 1");
  RequireOption(presence_min_points >= 1, "Objects.presence_min_points", "must be at least 1");
  RequireOption(presence_min_share > 0 && presence_min_share <= 1, "Objects.presence_min_share",
                "must be in (0, 1]");
  RequireOption(presence_search_radius > 0, "Objects.presence_search_radius",
                "must be positive (pixels)");
  RequireOption(yaw_min_points >= 3, "Objects.yaw_min_points", "must be at least 3");
  RequireOption(yaw_min_elongation >= 1, "Objects.yaw_min_elongation", "must be at least 1");
  RequireOption(plane_max_tilt_deg > 0 && plane_max_tilt_deg < 90, "Objects.plane_max_tilt_deg",
                "must be in (0, 90)");
  RequireOption(plane_inlier_share > 0, "Objects.plane_inlier_share", "must be positive");
  RequireOption(plane_iterations >= 1, "Objects.plane_iterations", "must be at least 1");
  RequireOption(keyframe_interval >= 1, "Objects.keyframe_interval", "must be at least 1");
}

void ReadSettings(const SettingsFile& file, ObjectsOptions* options) {
  std::vector<double> classes;
  if (file.Read("Objects.classes", &classes)) {
    options->classes.clear();
    for (double value : classes) {
      RequireOption(value == std::floor(value), "Objects.classes", "class ids are integers");
      options->classes.push_back(static_cast<int>(value));
    }
  }
  file.Read("Objects.min_confidence", &options->min_confidence);
  file.Read("Objects.border_margin", &options->border_margin);
  file.Read("Objects.nms_iou", &options->nms_iou);
  file.Read("Objects.min_association_score", &options->min_association_score);
  file.Read("Objects.predicted_box_frames", &options->predicted_box_frames);
  file.Read("Objects.max_ray_distance", &options->max_ray_distance);
  file.Read("Objects.min_reacquire_iou", &options->min_reacquire_iou);
  file.Read("Objects.candidate_min_observations", &options->candidate_min_observations);
  file.Read("Objects.candidate_min_parallax_deg", &options->candidate_min_parallax_deg);
  file.Read("Objects.candidate_max_missed_frames", &options->candidate_max_missed_frames);
  file.Read("Objects.candidate_gap_seconds", &options->candidate_gap_seconds);
  file.Read("Objects.min_inlier_share", &options->min_inlier_share);
  file.Read("Objects.min_sightings", &options->min_sightings);
  file.Read("Objects.probation_keyframes", &options->probation_keyframes);
  file.Read("Objects.max_rays", &options->max_rays);
  file.Read("Objects.max_sightings", &options->max_sightings);
  file.Read("Objects.merge_distance", &options->merge_distance);
  file.Read("Objects.merge_overlap", &options->merge_overlap);
  file.Read("Objects.duplicate_box_iou", &options->duplicate_box_iou);
  file.Read("Objects.merge_along_rays", &options->merge_along_rays);
  file.Read("Objects.join_candidates", &options->join_candidates);
  file.Read("Objects.restore_window", &options->restore_window);
  file.Read("Objects.restore_overlap", &options->restore_overlap);
  std::vector<double> up;
  if (file.Read("Objects.up", &up)) {
    RequireOption(up.size() == 3, "Objects.up", "needs 3 numbers");
    options->up = Eigen::Vector3d(up[0], up[1], up[2]);
  }
  file.Read("Objects.point_box_shrink", &options->point_box_shrink);
  file.Read("Objects.min_point_votes", &options->min_point_votes);
  file.Read("Objects.presence_min_points", &options->presence_min_points);
  file.Read("Objects.presence_min_share", &options->presence_min_share);
  file.Read("Objects.presence_search_radius", &options->presence_search_radius);
  file.Read("Objects.yaw_min_points", &options->yaw_min_points);
  file.Read("Objects.yaw_min_elongation", &options->yaw_min_elongation);
  file.Read("Objects.plane_max_tilt_deg", &options->plane_max_tilt_deg);
  file.Read("Objects.plane_inlier_share", &options->plane_inlier_share);
  file.Read("Objects.plane_iterations", &options->plane_iterations);
  file.Read("Objects.keyframe_interval", &options->keyframe_interval);
}

}  // namespace ocg
