#pragma once
// The object map as a mesh, for MeshLab, Open3D, Blender or RViz (docs/viewer.md): each
// live object's cuboid a closed box of 8 corners and 12 triangles, wound counter-clockwise
// seen from outside (normals point outwards), coloured by its OCG state in the snapshots'
// colours. Written as PLY (ASCII, a colour per vertex) or Wavefront OBJ (a material per
// state in a .mtl file beside it, and the vertex colours after each position, as MeshLab
// and Open3D read them). Map frame and units.

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "ocg/objects/object_map.h"

namespace ocg {

struct ObjectMesh {
  std::vector<ObjectView> objects;            // the live objects, in the order of their boxes
  std::vector<Eigen::Vector3d> vertices;      // 8 per object: object i's are 8i..8i+7
  std::vector<Eigen::Vector3f> colours;       // per vertex, RGB in [0, 1]
  std::vector<std::array<int, 3>> triangles;  // 12 per object, indices into vertices
};

// The boxes of the live objects (removed ones are left out: they are not in the map),
// gravity-aligned about up as the snapshots draw them. A size below 1 mm is drawn as 1 mm.
ObjectMesh MakeObjectMesh(const std::vector<ObjectView>& objects, const Eigen::Vector3d& up);

// The OCG state's name as the mesh files' materials and comments give it ("observed",
// "recently_observed", "unknown", "suspicious", "not_judged_yet").
std::string StateMaterialName(int state);

// Writes the mesh by path's extension: ".ply", or ".obj" (and the .mtl of the same name).
// Throws std::invalid_argument for another extension, FileError when a file cannot be
// written.
void WriteObjectMesh(const std::string& path, const ObjectMesh& mesh);

}  // namespace ocg
