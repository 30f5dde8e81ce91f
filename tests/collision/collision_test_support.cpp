#include "collision_test_support.hpp"

#include <gtest/gtest.h>

#include <cstdio>

#include "vaw/mass_properties.hpp"
#include "vaw/scene_loader.hpp"

namespace vaw::ctest {

const ImporterRegistry& importers() {
  static ImporterRegistry* registry = [] {
    auto* r = new ImporterRegistry();
    for (const auto& p : r->loadPlugins(VAW_BUILD_PLUGIN_DIR)) ADD_FAILURE() << p;
    return r;
  }();
  EXPECT_FALSE(registry->importerNames().empty()) << "no importer plugin in " << VAW_BUILD_PLUGIN_DIR;
  return *registry;
}

std::filesystem::path resources() { return VAW_BUILD_RESOURCE_DIR; }

std::string um(double metres) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.2f um", metres * 1e6);
  return buf;
}

Assembly loadBundled(const std::string& sceneFile) { return loadScene(resources() / "scenes" / sceneFile, importers()); }

PartId SceneBuilder::part(const std::string& name, TriMesh mesh, const Eigen::Isometry3d& pose, double density) {
  Part p;
  p.id = a.parts.size();
  p.name = name;
  p.pose = pose;
  p.mass = massPropertiesFromMesh(mesh, density);
  p.mesh = std::make_shared<const TriMesh>(std::move(mesh));
  p.shapeSource = "test mesh";
  a.parts.push_back(std::move(p));
  return a.parts.size() - 1;
}

std::size_t SceneBuilder::environment(const std::string& name, TriMesh mesh, const Eigen::Isometry3d& pose,
                                      const std::string& shapeSource) {
  EnvironmentObject e;
  e.name = name;
  e.kind = "table";
  e.pose = pose;
  e.mesh = std::make_shared<const TriMesh>(std::move(mesh));
  e.shapeSource = shapeSource;
  a.environment.push_back(std::move(e));
  return a.environment.size() - 1;
}

Constraint SceneBuilder::mate(PartId p, const Eigen::Vector3d& partPoint, const Eigen::Vector3d& partNormal,
                              const Eigen::Vector3d& basePoint, const Eigen::Vector3d& baseNormal) {
  Constraint c;
  c.type = Constraint::Type::Mate;
  c.part = p;
  c.partPlane = {partPoint, partNormal.normalized()};
  c.basePlane = {basePoint, baseNormal.normalized()};
  a.constraints.push_back(c);
  return c;
}

Constraint SceneBuilder::insert(PartId p, const Eigen::Vector3d& partPoint, const Eigen::Vector3d& partDir,
                                const Eigen::Vector3d& basePoint, const Eigen::Vector3d& baseDir) {
  Constraint c;
  c.type = Constraint::Type::Insert;
  c.part = p;
  c.partAxis = {partPoint, partDir.normalized()};
  c.baseAxis = {basePoint, baseDir.normalized()};
  a.constraints.push_back(c);
  return c;
}

TriMesh gridBox(const Eigen::Vector3d& size, int n) {
  TriMesh m;
  const Eigen::Vector3d h = size / 2.0;
  // Each face: axis a fixed at +-h[a], the other two axes b, c gridded.
  for (int a = 0; a < 3; ++a)
    for (double side : {-1.0, 1.0}) {
      const int b = (a + 1) % 3, c = (a + 2) % 3;
      const int first = static_cast<int>(m.vertices.size());
      for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) {
          Eigen::Vector3d v;
          v[a] = side * h[a];
          v[b] = -h[b] + size[b] * i / n;
          v[c] = -h[c] + size[c] * j / n;
          m.vertices.push_back(v);
        }
      auto id = [&](int i, int j) { return first + i * (n + 1) + j; };
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          // (b, c, a) is right-handed, so counter-clockwise in (b, c) faces +a.
          if (side > 0) {
            m.triangles.emplace_back(id(i, j), id(i + 1, j), id(i + 1, j + 1));
            m.triangles.emplace_back(id(i, j), id(i + 1, j + 1), id(i, j + 1));
          } else {
            m.triangles.emplace_back(id(i, j), id(i + 1, j + 1), id(i + 1, j));
            m.triangles.emplace_back(id(i, j), id(i, j + 1), id(i + 1, j + 1));
          }
        }
    }
  weldVertices(m, 1e-12);
  return m;
}

}  // namespace vaw::ctest
