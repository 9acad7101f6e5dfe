#include "ocg/objects/cuboid_json.h"

#include <stdexcept>
#include <vector>

namespace ocg {

nlohmann::json VectorJson(const Eigen::Vector3d& vector) {
  return {vector.x(), vector.y(), vector.z()};
}

Eigen::Vector3d VectorFromJson(const nlohmann::json& json) {
  const auto values = json.get<std::vector<double>>();
  if (values.size() != 3) throw std::invalid_argument("expected 3 numbers");
  return {values[0], values[1], values[2]};
}

nlohmann::json CuboidJson(const Cuboid& cuboid) {
  return {{"centre", VectorJson(cuboid.centre)},
          {"size", VectorJson(cuboid.size)},
          {"yaw", cuboid.yaw}};
}

Cuboid CuboidFromJson(const nlohmann::json& json) {
  Cuboid cuboid;
  cuboid.centre = VectorFromJson(json.at("centre"));
  cuboid.size = VectorFromJson(json.at("size"));
  cuboid.yaw = json.at("yaw").get<double>();
  return cuboid;
}

}  // namespace ocg
