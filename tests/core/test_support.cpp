#include "test_support.hpp"

#include <gtest/gtest.h>

#include <sstream>

namespace vaw::test {

std::string asciiStl(const TriMesh& mesh) {
  std::ostringstream s;
  s.precision(17);
  s << "solid test\n";
  for (const auto& t : mesh.triangles) {
    s << " facet normal 0 0 0\n  outer loop\n";
    for (int k = 0; k < 3; ++k) {
      const auto& v = mesh.vertices[static_cast<std::size_t>(t[k])];
      s << "   vertex " << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
    }
    s << "  endloop\n endfacet\n";
  }
  s << "endsolid test\n";
  return s.str();
}

}  // namespace vaw::test
