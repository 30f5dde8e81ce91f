// The assimp plugin reads the formats a CAD user exports: STL (ASCII and binary), OBJ, PLY and glTF 2.0.
#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>

#include "test_support.hpp"
#include "vaw/mass_properties.hpp"
#include "vaw/primitives.hpp"
#include "vaw/scene_loader.hpp"

using namespace vaw;

namespace {

const TriMesh& cube() {
  static const TriMesh m = [] {
    TriMesh b = primitives::box({2, 2, 2});
    b.transform(Eigen::Isometry3d(Eigen::Translation3d(1, 1, 1)));
    return b;
  }();
  return m;
}

std::string binaryStl(const TriMesh& m) {
  std::string out(80, ' ');
  auto put = [&](const void* p, std::size_t n) { out.append(static_cast<const char*>(p), n); };
  const auto count = static_cast<std::uint32_t>(m.triangles.size());
  put(&count, 4);
  for (const auto& t : m.triangles) {
    const float normal[3] = {0, 0, 0};
    put(normal, 12);
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3f v = m.vertices[static_cast<std::size_t>(t[k])].cast<float>();
      put(v.data(), 12);
    }
    const std::uint16_t attr = 0;
    put(&attr, 2);
  }
  return out;
}

std::string obj(const TriMesh& m) {
  std::ostringstream s;
  for (const auto& v : m.vertices) s << "v " << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
  s << "o cube\n";
  for (const auto& t : m.triangles) s << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
  return s.str();
}

std::string ply(const TriMesh& m) {
  std::ostringstream s;
  s << "ply\nformat ascii 1.0\nelement vertex " << m.vertices.size() << "\nproperty float x\nproperty float y\nproperty float z\n"
    << "element face " << m.triangles.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& v : m.vertices) s << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
  for (const auto& t : m.triangles) s << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
  return s.str();
}

std::string base64(const std::string& in) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const unsigned n = (static_cast<unsigned char>(in[i]) << 16) | (static_cast<unsigned char>(in[i + 1]) << 8) |
                       static_cast<unsigned char>(in[i + 2]);
    for (int k = 18; k >= 0; k -= 6) out += table[(n >> k) & 63];
  }
  if (i < in.size()) {
    unsigned n = static_cast<unsigned char>(in[i]) << 16;
    if (i + 1 < in.size()) n |= static_cast<unsigned char>(in[i + 1]) << 8;
    out += table[(n >> 18) & 63];
    out += table[(n >> 12) & 63];
    out += i + 1 < in.size() ? table[(n >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

// Two cubes as two named nodes under a named root: the hierarchy must survive import.
std::string gltf(const TriMesh& m) {
  std::string buffer;
  for (const auto& v : m.vertices) {
    const Eigen::Vector3f f = v.cast<float>();
    buffer.append(reinterpret_cast<const char*>(f.data()), 12);
  }
  const std::size_t vbytes = buffer.size();
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) {
      const auto idx = static_cast<std::uint32_t>(t[k]);
      buffer.append(reinterpret_cast<const char*>(&idx), 4);
    }
  nlohmann::json j = {
      {"asset", {{"version", "2.0"}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0}}}}},
      {"nodes", {{{"name", "pair"}, {"children", {1, 2}}}, {{"name", "left"}, {"mesh", 0}},
                 {{"name", "right"}, {"mesh", 0}, {"translation", {3.0, 0.0, 0.0}}}}},
      {"meshes", {{{"name", "cube"}, {"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}}}},
      {"buffers", {{{"byteLength", buffer.size()}, {"uri", "data:application/octet-stream;base64," + base64(buffer)}}}},
      {"bufferViews", {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", vbytes}},
                       {{"buffer", 0}, {"byteOffset", vbytes}, {"byteLength", buffer.size() - vbytes}}}},
      {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", m.vertices.size()}, {"type", "VEC3"},
                      {"min", {0.0, 0.0, 0.0}}, {"max", {2.0, 2.0, 2.0}}},
                     {{"bufferView", 1}, {"componentType", 5125}, {"count", 3 * m.triangles.size()}, {"type", "SCALAR"}}}}};
  return j.dump();
}

struct Format {
  const char* file;
  std::function<std::string(const TriMesh&)> write;
};

class Importers : public ::testing::TestWithParam<Format> {};

TEST_P(Importers, ReadsAClosedCube) {
  const auto dir = test::tempDir();
  const auto path = test::writeFile(dir / GetParam().file, GetParam().write(cube()));
  LoadOptions options;
  options.bareMeshUnits = LengthUnit::Metre;
  options.bareMeshDensity = 1000.0;
  const Assembly a = loadMeshFile(path, test::importers(), options);
  ASSERT_EQ(a.parts.size(), 1u);
  const Part& p = a.parts[0];
  EXPECT_NEAR(p.mass.volume, 8.0, 1e-12);
  EXPECT_NEAR(p.mass.mass, 8000.0, 1e-9);
  EXPECT_LE((p.mass.centerOfMass - Eigen::Vector3d(1, 1, 1)).norm(), 1e-12);
  EXPECT_EQ(p.mesh->triangleCount(), 12u);
  EXPECT_EQ(p.mesh->vertices.size(), 8u) << "corners shared after welding";
}

INSTANTIATE_TEST_SUITE_P(Formats, Importers,
                         ::testing::Values(Format{"cube.stl", test::asciiStl}, Format{"cube_binary.stl", binaryStl},
                                           Format{"cube.obj", obj}, Format{"cube.ply", ply}),
                         [](const auto& p) {
                           std::string n = p.param.file;
                           for (auto& c : n) if (c == '.') c = '_';
                           return n;
                         });

TEST(Importers, GltfKeepsNodeHierarchyAndIsMetres) {
  const auto dir = test::tempDir();
  const auto path = test::writeFile(dir / "pair.gltf", gltf(cube()));
  const Assembly a = loadMeshFile(path, test::importers());
  EXPECT_EQ(a.units, LengthUnit::Metre) << "glTF is metres by specification";
  double volume = 0;
  for (const auto& p : a.parts) volume += p.mass.volume;
  EXPECT_NEAR(volume, 16.0, 1e-9);
  // Names from the file appear in the scene tree.
  std::function<bool(const TreeNode&, const std::string&)> has = [&](const TreeNode& n, const std::string& name) {
    if (n.name == name) return true;
    for (const auto& c : n.children)
      if (has(c, name)) return true;
    return false;
  };
  EXPECT_TRUE(has(a.tree, "left"));
  EXPECT_TRUE(has(a.tree, "right"));
}

TEST(Importers, BareStlDefaultsToMillimetres) {
  const auto dir = test::tempDir();
  const auto path = test::writeFile(dir / "cube.stl", binaryStl(cube()));
  const Assembly a = loadMeshFile(path, test::importers());
  EXPECT_EQ(a.units, LengthUnit::Millimetre);
  EXPECT_NEAR(a.parts[0].mass.volume, 8e-9, 1e-20);
  EXPECT_FALSE(a.warnings.empty()) << "assumed units must be said";
}

TEST(Importers, RegistryKnowsTheFormats) {
  const auto exts = test::importers().extensions();
  for (const char* e : {"stl", "obj", "ply", "gltf", "glb"})
    EXPECT_NE(std::find(exts.begin(), exts.end(), e), exts.end()) << e;
  EXPECT_EQ(std::find(exts.begin(), exts.end(), "json"), exts.end()) << "JSON is the scene format";
}

TEST(Importers, BrokenPluginIsReportedNotLoaded) {
  const auto dir = test::tempDir();
  test::writeFile(dir / "libvaw_import_fake.so", "not an ELF file");
  ImporterRegistry r;
  const auto problems = r.loadPlugins(dir);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(problems[0].find("libvaw_import_fake.so"), std::string::npos);
  EXPECT_TRUE(r.importerNames().empty());
}

}  // namespace
