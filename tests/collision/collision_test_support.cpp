#include "collision_test_support.hpp"

#include <gtest/gtest.h>

#include <cstdio>

#include "vaw/mass_properties.hpp"
#include "vaw/scene_loader.hpp"

namespace vaw::ctest {

std::string um(double metres) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.2f um", metres * 1e6);
  return buf;
}

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


}  // namespace vaw::ctest
