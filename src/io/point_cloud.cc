#include "ocg/io/point_cloud.h"

#include <algorithm>
#include <iomanip>
#include <sstream>

#include "ocg/core/file_io.h"
#include "ocg/io/text_lines.h"

namespace ocg {

void WritePlyPoints(const std::string& path, const std::vector<Eigen::Vector3d>& points) {
  std::ostringstream out;
  out << "ply\nformat ascii 1.0\ncomment OCG-SLAM map points\nelement vertex " << points.size()
      << "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  out << std::setprecision(7);
  for (const Eigen::Vector3d& p : points) out << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  WriteFileAtomically(path, out.str());
}

std::vector<Eigen::Vector3d> ReadPlyPoints(const std::string& path) {
  std::istringstream in(ReadTextFile(path));
  std::string line;
  int line_number = 0;
  const auto fail = [&](const std::string& message) {
    ThrowParseError(path, line_number, message);
  };
  long long vertices = -1;
  int properties = 0, x = -1, y = -1, z = -1;
  bool in_vertex = false;
  while (std::getline(in, line)) {
    ++line_number;
    std::istringstream words(line);
    std::string word;
    words >> word;
    if (line_number == 1 && word != "ply") fail("not a PLY file (no 'ply' line)");
    if (word == "format") {
      std::string format;
      words >> format;
      if (format != "ascii") fail("only ASCII PLY is read, this is '" + format + "'");
    } else if (word == "element") {
      std::string name;
      long long count = 0;
      words >> name >> count;
      in_vertex = name == "vertex";
      if (in_vertex) vertices = count;
    } else if (word == "property" && in_vertex) {
      std::string type, name;
      words >> type >> name;
      if (name == "x") x = properties;
      if (name == "y") y = properties;
      if (name == "z") z = properties;
      ++properties;
    } else if (word == "end_header") {
      break;
    }
  }
  if (vertices < 0) fail("no 'element vertex' in the header");
  if (x < 0 || y < 0 || z < 0) fail("the vertices have no x, y, z properties");
  std::vector<Eigen::Vector3d> points;
  // The header's count is not trusted for memory: every vertex takes at least 6 bytes
  // ("x y z\n"), so a count the file cannot hold fails below at its end, not here.
  const auto left = static_cast<long long>(in.rdbuf()->in_avail());
  points.reserve(static_cast<std::size_t>(std::min(vertices, std::max(0LL, left) / 6 + 1)));
  std::vector<double> values(static_cast<std::size_t>(properties));
  for (long long i = 0; i < vertices; ++i) {
    ++line_number;
    if (!std::getline(in, line))
      fail("ends after " + std::to_string(i) + " of " + std::to_string(vertices) + " vertices");
    std::istringstream words(line);
    for (double& value : values) {
      if (!(words >> value)) fail("expected " + std::to_string(properties) + " numbers");
    }
    points.emplace_back(values[static_cast<std::size_t>(x)], values[static_cast<std::size_t>(y)],
                        values[static_cast<std::size_t>(z)]);
  }
  return points;
}

}  // namespace ocg
