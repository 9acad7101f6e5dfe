#pragma once
// Map points as an ASCII PLY file (x y z per vertex), readable by MeshLab, CloudCompare
// and Open3D: `map_points.ply` of a SLAM run.

#include <string>
#include <vector>

#include <Eigen/Core>

namespace ocg {

// Writes atomically. Throws FileError naming the path.
void WritePlyPoints(const std::string& path, const std::vector<Eigen::Vector3d>& points);
// Reads the vertices' x, y, z of an ASCII PLY file (other vertex properties are skipped).
// Throws FileError when it cannot be read, ParseError naming file and line otherwise.
std::vector<Eigen::Vector3d> ReadPlyPoints(const std::string& path);

}  // namespace ocg
