#include "ocg/viewer/object_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>
#include <sstream>
#include <stdexcept>

#include "ocg/core/coco.h"
#include "ocg/core/file_io.h"
#include "ocg/viewer/map_view.h"

namespace ocg {
namespace {

int ToByte(float value) {
  return static_cast<int>(std::lround(255.0f * std::clamp(value, 0.0f, 1.0f)));
}

std::string Number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6f", value);
  return text;
}

std::string ObjectComment(const ObjectView& object, std::size_t index) {
  return "object " + std::to_string(object.id) + " " + CocoClassName(object.class_id) + ", state " +
         StateMaterialName(object.state) + ", vertices " + std::to_string(8 * index) + "-" +
         std::to_string(8 * index + 7);
}

void WritePly(const std::string& path, const ObjectMesh& mesh) {
  std::ostringstream out;
  out << "ply\nformat ascii 1.0\n"
      << "comment OCG-SLAM object map: one closed box per live object, coloured by OCG state\n";
  for (std::size_t i = 0; i < mesh.objects.size(); ++i)
    out << "comment " << ObjectComment(mesh.objects[i], i) << "\n";
  out << "element vertex " << mesh.vertices.size() << "\n"
      << "property float x\nproperty float y\nproperty float z\n"
      << "property uchar red\nproperty uchar green\nproperty uchar blue\n"
      << "element face " << mesh.triangles.size() << "\n"
      << "property list uchar int vertex_indices\nend_header\n";
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Eigen::Vector3d& v = mesh.vertices[i];
    const Eigen::Vector3f& c = mesh.colours[i];
    out << Number(v.x()) << ' ' << Number(v.y()) << ' ' << Number(v.z()) << ' ' << ToByte(c.x())
        << ' ' << ToByte(c.y()) << ' ' << ToByte(c.z()) << "\n";
  }
  for (const std::array<int, 3>& t : mesh.triangles)
    out << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << "\n";
  WriteFileAtomically(path, out.str());
}

void WriteObj(const std::string& path, const ObjectMesh& mesh) {
  const std::filesystem::path mtl_path = std::filesystem::path(path).replace_extension(".mtl");
  std::ostringstream mtl;
  mtl << "# OCG-SLAM object map: one material per OCG state\n";
  std::set<int> states;
  for (const ObjectView& object : mesh.objects) states.insert(object.state);
  for (int state : states) {
    const Eigen::Vector3f colour = StateColour(state, false);
    mtl << "newmtl " << StateMaterialName(state) << "\nKd " << Number(colour.x()) << ' '
        << Number(colour.y()) << ' ' << Number(colour.z()) << "\nKa 0 0 0\nd 1\nillum 1\n";
  }
  std::ostringstream obj;
  obj << "# OCG-SLAM object map: one closed box per live object, coloured by OCG state\n"
      << "mtllib " << mtl_path.filename().string() << "\n";
  for (std::size_t i = 0; i < mesh.objects.size(); ++i) {
    const ObjectView& object = mesh.objects[i];
    obj << "# " << ObjectComment(object, i) << "\n"
        << "o object_" << object.id << "_" << CocoClassName(object.class_id) << "\n";
    for (std::size_t v = 8 * i; v < 8 * i + 8; ++v) {
      const Eigen::Vector3d& p = mesh.vertices[v];
      const Eigen::Vector3f& c = mesh.colours[v];
      obj << "v " << Number(p.x()) << ' ' << Number(p.y()) << ' ' << Number(p.z()) << ' '
          << Number(c.x()) << ' ' << Number(c.y()) << ' ' << Number(c.z()) << "\n";
    }
    obj << "usemtl " << StateMaterialName(object.state) << "\n";
    for (std::size_t t = 12 * i; t < 12 * i + 12; ++t) {
      const std::array<int, 3>& triangle = mesh.triangles[t];  // OBJ counts from 1
      obj << "f " << triangle[0] + 1 << ' ' << triangle[1] + 1 << ' ' << triangle[2] + 1 << "\n";
    }
  }
  WriteFileAtomically(mtl_path.string(), mtl.str());
  WriteFileAtomically(path, obj.str());
}

}  // namespace

std::string StateMaterialName(int state) {
  switch (state) {
    case 1:
      return "observed";
    case 2:
      return "recently_observed";
    case 3:
      return "unknown";
    case 4:
      return "suspicious";
    default:
      return "not_judged_yet";
  }
}

ObjectMesh MakeObjectMesh(const std::vector<ObjectView>& objects, const Eigen::Vector3d& up) {
  const Eigen::Matrix3d R_wg = GravityFrame(up);
  ObjectMesh mesh;
  for (const ObjectView& object : objects) {
    if (object.removed) continue;
    const int first = static_cast<int>(mesh.vertices.size());
    Cuboid cuboid = object.cuboid;
    cuboid.size = cuboid.size.cwiseMax(1e-3);
    for (const Eigen::Vector3d& corner : CuboidCorners(cuboid, R_wg)) {
      mesh.vertices.push_back(corner);
      mesh.colours.push_back(StateColour(object.state, false));
    }
    // Corner bits: x 1, y 2, z 4 (CuboidCorners). The face on side `high` of axis a, its
    // corners ordered round the axes b, c that follow a: counter-clockwise seen from
    // outside when high (b x c = a), reversed when not.
    for (int a = 0; a < 3; ++a) {
      const int b = (a + 1) % 3, c = (a + 2) % 3;
      for (int high = 0; high < 2; ++high) {
        const int base = high << a;
        std::array<int, 4> quad = {base, base | (1 << b), base | (1 << b) | (1 << c),
                                   base | (1 << c)};
        if (!high) std::reverse(quad.begin(), quad.end());
        mesh.triangles.push_back({first + quad[0], first + quad[1], first + quad[2]});
        mesh.triangles.push_back({first + quad[0], first + quad[2], first + quad[3]});
      }
    }
    mesh.objects.push_back(object);
  }
  return mesh;
}

void WriteObjectMesh(const std::string& path, const ObjectMesh& mesh) {
  const std::string extension = std::filesystem::path(path).extension().string();
  if (extension == ".ply") {
    WritePly(path, mesh);
  } else if (extension == ".obj") {
    WriteObj(path, mesh);
  } else {
    throw std::invalid_argument("mesh file '" + path + "': the extension must be .ply or .obj");
  }
}

}  // namespace ocg
