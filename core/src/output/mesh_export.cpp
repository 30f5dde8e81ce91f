#include "vaw/mesh_export.hpp"

#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace vaw {

namespace {
void put(std::string& out, float f) {
  char b[4];
  std::memcpy(b, &f, 4);  // STL is little-endian, as every machine vaw builds for
  out.append(b, 4);
}
}  // namespace

std::string binaryStl(const TriMesh& mesh, double unitsPerMetre, std::string_view header) {
  if (mesh.triangles.size() > std::numeric_limits<std::uint32_t>::max())
    throw std::invalid_argument("a binary STL holds at most 2^32 - 1 facets, not " + std::to_string(mesh.triangles.size()));
  std::string out(80, ' ');
  out.replace(0, std::min<std::size_t>(80, header.size()), header.substr(0, 80));
  const auto count = static_cast<std::uint32_t>(mesh.triangles.size());
  char c[4];
  std::memcpy(c, &count, 4);
  out.append(c, 4);
  out.reserve(out.size() + 50 * mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d& a = mesh.vertices[t[0]];
    const Eigen::Vector3d& b = mesh.vertices[t[1]];
    const Eigen::Vector3d& d = mesh.vertices[t[2]];
    const Eigen::Vector3d n = (b - a).cross(d - a).normalized();
    for (int i = 0; i < 3; ++i) put(out, static_cast<float>(n.allFinite() ? n[i] : 0.0));
    for (const Eigen::Vector3d* p : {&a, &b, &d})
      for (int i = 0; i < 3; ++i) put(out, static_cast<float>(unitsPerMetre * (*p)[i]));
    out.append(2, '\0');
  }
  return out;
}

}  // namespace vaw
