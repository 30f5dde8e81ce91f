#pragma once
// Scenes for the collision tests: built from vaw::primitives, or the bundled ones loaded through the
// assimp plugin of the build tree (VAW_BUILD_PLUGIN_DIR / VAW_BUILD_RESOURCE_DIR).
#include <filesystem>

#include "bundled.hpp"
#include <string>

#include "vaw/assembly.hpp"
#include "vaw/collision/collision_world.hpp"
#include "vaw/importer.hpp"

namespace vaw::ctest {

using vaw::test::importers;
using vaw::test::loadBundled;
using vaw::test::resources;

// A length for the test report (RecordProperty), in micrometres.
std::string um(double metres);

inline Eigen::Isometry3d at(double x, double y, double z) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.translation() = Eigen::Vector3d(x, y, z);
  return p;
}

// An assembly made in code. Parts get mesh mass properties (steel unless given).
struct SceneBuilder {
  Assembly a;
  PartId part(const std::string& name, TriMesh mesh, const Eigen::Isometry3d& pose, double density = 7850.0);
  std::size_t environment(const std::string& name, TriMesh mesh, const Eigen::Isometry3d& pose,
                          const std::string& shapeSource = "mesh");
  void base(PartId p) { a.base = p; }
  // A mate: the part's face with outward normal partNormal through partPoint (part frame) on the base's face.
  Constraint mate(PartId p, const Eigen::Vector3d& partPoint, const Eigen::Vector3d& partNormal,
                  const Eigen::Vector3d& basePoint, const Eigen::Vector3d& baseNormal);
  Constraint insert(PartId p, const Eigen::Vector3d& partPoint, const Eigen::Vector3d& partDir,
                    const Eigen::Vector3d& basePoint, const Eigen::Vector3d& baseDir);
};


}  // namespace vaw::ctest
