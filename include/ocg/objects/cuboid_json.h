#pragma once
// Vectors and cuboids as the objects module's JSON files hold them (objects.json,
// changes.json, ocg_diff's JSON): a vector is [x, y, z]; a cuboid is {"centre": [x, y, z],
// "size": [x, y, z], "yaw": radians about up}, world frame, map units. One writer and one
// reader for every file and every reader of them (the viewer's too), so they cannot
// drift apart.

#include <nlohmann/json.hpp>

#include "ocg/objects/box.h"

namespace ocg {

nlohmann::json VectorJson(const Eigen::Vector3d& vector);
// Throws std::invalid_argument unless json holds 3 numbers (nlohmann::json::exception when
// it is no array of numbers).
Eigen::Vector3d VectorFromJson(const nlohmann::json& json);

nlohmann::json CuboidJson(const Cuboid& cuboid);
// Throws nlohmann::json::exception naming a missing key, or as VectorFromJson.
Cuboid CuboidFromJson(const nlohmann::json& json);

}  // namespace ocg
