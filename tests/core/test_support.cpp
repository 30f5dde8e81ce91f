#include "test_support.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <random>
#include <sstream>

namespace vaw::test {

namespace {
struct TempRoot {
  std::filesystem::path path;
  TempRoot() {
    std::random_device rd;
    path = std::filesystem::temp_directory_path() / ("vaw-test-" + std::to_string(rd()));
    std::filesystem::create_directories(path);
  }
  ~TempRoot() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
};
}  // namespace

std::filesystem::path tempDir() {
  static TempRoot root;
  static int counter = 0;
  auto dir = root.path / std::to_string(++counter);
  std::filesystem::create_directories(dir);
  return dir;
}

std::filesystem::path writeFile(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

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
