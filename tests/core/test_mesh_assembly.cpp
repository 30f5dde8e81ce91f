// A mesh file of several parts (OBJ objects, glTF nodes) made ready to assemble like a STEP file: the
// constraints found in the collision module's surface patches, the parts laid out beside the heaviest,
// saved and reopened, and assembled in order in the world. The fixture is a shaft standing on a base
// plate with a sleeve on the shaft, its cylinders tessellated with different numbers of segments.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>
#include <sstream>

#include "assembler.hpp"
#include "bundled.hpp"
#include "files.hpp"
#include "vaw/cad_assembly.hpp"
#include "vaw/mass_properties.hpp"
#include "vaw/primitives.hpp"
#include "vaw/scene_loader.hpp"
#include "vaw/sim/scene.hpp"
#include "vaw/sim/scene_file.hpp"

namespace {

namespace fs = std::filesystem;
using namespace vaw;

struct Object {
  std::string name;
  TriMesh mesh;
};

std::string obj(const std::vector<Object>& objects) {
  std::ostringstream s;
  std::size_t offset = 1;
  for (const auto& o : objects) {
    s << "o " << o.name << '\n';
    for (const auto& v : o.mesh.vertices) s << "v " << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
    for (const auto& t : o.mesh.triangles) s << "f " << t[0] + offset << ' ' << t[1] + offset << ' ' << t[2] + offset << '\n';
    offset += o.mesh.vertices.size();
  }
  return s.str();
}

TriMesh moved(TriMesh m, const Eigen::Vector3d& t) {
  m.transform(Eigen::Isometry3d(Eigen::Translation3d(t)));
  return m;
}

// Millimetres, the base plate's top at z = 0: a 100 mm shaft (r 10, 48 segments) standing on it, and a
// 30 mm sleeve (bore r 10, 32 segments) on the shaft, resting on the plate. The shaft is heavier than the
// sleeve, so the sleeve goes onto the shaft.
fs::path shaftAndSleeve() {
  return test::writeFile(test::tempDir() / "shaft-and-sleeve.obj",
                         obj({{"plate", moved(primitives::box({200, 200, 20}), {0, 0, -10})},
                              {"shaft", moved(primitives::cylinder(10, 100, 48), {0, 0, 50})},
                              {"sleeve", moved(primitives::tube(20, 10, 30, 32), {0, 0, 15})}}));
}

std::multiset<std::string> described(const Assembly& a) {
  std::multiset<std::string> out;
  for (const Constraint& c : a.constraints)
    out.insert(std::string(name(c.type)) + ' ' + a.parts[c.part].name + ' ' + a.parts[c.partner.value_or(*a.base)].name);
  return out;
}

TEST(MeshAssembly, SurfacePatchesBecomeContiguousFaces) {
  Eigen::Vector3d centroid;
  const auto solid = cadSolidFromMesh(moved(primitives::tube(0.02, 0.01, 0.03, 32), {1, 2, 3}), "sleeve", centroid);
  EXPECT_LT((centroid - Eigen::Vector3d(1, 2, 3)).norm(), 1e-12);
  int cylinders = 0, planes = 0;
  std::size_t next = 0;
  for (const CadFace& f : solid->faces) {
    EXPECT_EQ(f.firstTriangle, next) << "faces' triangles follow one another";
    next += f.triangleCount;
    if (f.surface == CadFace::Surface::Cylinder) {
      ++cylinders;
      EXPECT_NEAR(f.radius, f.convex ? 0.02 : 0.01, 1e-12);
      EXPECT_NEAR(std::abs(f.direction.z()), 1.0, 1e-12);
      EXPECT_NEAR(f.axialMax - f.axialMin, 0.03, 1e-12);
      EXPECT_LT(f.point.head<2>().norm(), 1e-12) << "the axis through the solid's origin, its centroid";
    } else if (f.surface == CadFace::Surface::Plane) {
      ++planes;
      EXPECT_NEAR(std::abs(f.direction.z()), 1.0, 1e-12);
      EXPECT_NEAR(std::abs(f.point.z()), 0.015, 1e-12);
    }
  }
  EXPECT_EQ(next, solid->mesh.triangleCount()) << "every triangle in one face";
  EXPECT_EQ(cylinders, 2);
  EXPECT_EQ(planes, 2) << "the two annular ends";
  EXPECT_NEAR(solid->volume, integrateVolume(solid->mesh).volume, 1e-15);
}

TEST(MeshAssembly, ConstraintsAreFoundInTheSurfacePatches) {
  const Assembly a = loadAny(shaftAndSleeve(), test::importers());
  ASSERT_EQ(a.parts.size(), 3u);
  ASSERT_TRUE(a.base.has_value());
  EXPECT_EQ(a.parts[*a.base].name, "plate") << "the heaviest part is the base";
  EXPECT_EQ(described(a), (std::multiset<std::string>{"mate shaft plate", "insert sleeve shaft", "mate sleeve plate"}));
  for (const Constraint& c : a.constraints) {
    ASSERT_TRUE(c.found.has_value());
    if (c.type == Constraint::Type::Insert) {
      // Within the 1e-5 mm an OBJ file's six digits keep.
      EXPECT_NEAR(c.found->partRadius, 0.010, 1e-8) << "the circle through the vertices, whatever the segments";
      EXPECT_NEAR(c.found->clearance, 0.0, 1e-8);
      EXPECT_NEAR(c.found->overlap, 0.030, 1e-8) << "the sleeve's length on the shaft";
    } else {
      EXPECT_GT(c.found->overlap, 0.0);
    }
  }
  for (const Part& p : a.parts) {
    EXPECT_EQ(p.massSource, MassSource::Mesh) << p.name << ": a mesh has no exact solid";
    EXPECT_FALSE(p.fileMass.has_value());
    ASSERT_TRUE(p.cad != nullptr);
  }
  const Part& shaft = a.parts[*a.findPart("shaft")];
  const double prism = 48 * 0.5 * 0.01 * 0.01 * std::sin(2 * std::numbers::pi / 48) * 0.1;
  EXPECT_NEAR(shaft.mass.volume, prism, 1e-6 * prism)
      << "the 48-sided prism's volume, in metres: the file was read as millimetres";
  EXPECT_EQ(a.units, LengthUnit::Millimetre);
  EXPECT_TRUE(a.settings.placeAtRest);
  ASSERT_EQ(a.environment.size(), 1u);
  EXPECT_EQ(a.environment[0].kind, "table");
  // Laid out beside the plate, standing as assembled.
  const Part& sleeve = a.parts[*a.findPart("sleeve")];
  EXPECT_TRUE(sleeve.pose.linear().isApprox(sleeve.finalPose->linear(), 1e-12));
  EXPECT_GT(sleeve.pose.translation().x(), 0.1) << "beside the plate, not on it";
}

TEST(MeshAssembly, PartsTouchingAtAnEdgeOrApartAreNoConstraint) {
  const fs::path file = test::writeFile(test::tempDir() / "blocks.obj",
                                        obj({{"big", moved(primitives::box({40, 40, 40}), {0, 0, 20})},
                                             {"edge", moved(primitives::box({20, 20, 20}), {30, 0, 50})},
                                             {"apart", moved(primitives::box({20, 20, 20}), {100, 0, 10})}}));
  const Assembly a = loadAny(file, test::importers());
  ASSERT_EQ(a.parts.size(), 3u);
  EXPECT_TRUE(a.constraints.empty()) << a.constraints.size() << " constraints, first " << a.constraints.front().name;
}

TEST(MeshAssembly, ASavedSceneKeepsTheAssumedUnitAndReopensIdentically) {
  const fs::path file = shaftAndSleeve();
  LoadOptions inches;
  inches.bareMeshUnits = LengthUnit::Inch;
  const Assembly a = loadAny(file, test::importers(), inches);
  const sim::World world(a, sim::settingsFor(a));
  const fs::path scene = file.parent_path() / "shaft-and-sleeve.vaw.json";
  sim::saveScene(a, world, scene);
  const Assembly b = loadAny(scene, test::importers());
  EXPECT_EQ(b.cadFile, file);
  EXPECT_EQ(described(b), described(a));
  EXPECT_NEAR(b.parts[*b.findPart("shaft")].mass.volume, a.parts[*a.findPart("shaft")].mass.volume, 1e-15)
      << "read in inches again, not in the default millimetres";
  EXPECT_EQ(sim::Scene::build(b)->contentHash(), sim::Scene::build(Assembly(a))->contentHash());
}

TEST(MeshAssembly, TheSleeveGoesOntoThePlacedShaft) {
  const Assembly a = loadAny(shaftAndSleeve(), test::importers());
  test::Assembler as(a);
  // Before its shaft is placed, the sleeve at home is refused.
  as.carry("sleeve", as.above("sleeve", 0.0));
  EXPECT_NE(as.state("sleeve"), interact::PartState::Placed);
  ASSERT_FALSE(as.world().refusals().empty());
  EXPECT_NE(as.world().refusals().front().reason.find("its partner shaft is not placed yet"), std::string::npos)
      << as.world().refusals().front().reason;
  as.settle();
  Eigen::Isometry3d aside = a.parts[*a.findPart("sleeve")].pose;
  aside.translation().z() += 0.001;
  as.carry("sleeve", aside);
  as.settle();

  // The shaft let go 2 mm over its place stands on the plate, PLACED; then the sleeve, 5 mm up, slides down it.
  as.carry("shaft", as.above("shaft", 2.0));
  as.settle();
  EXPECT_EQ(as.state("shaft"), interact::PartState::Placed) << as.events("shaft", true);
  as.carry("sleeve", as.above("sleeve", 5.0));
  as.settle();
  EXPECT_EQ(as.state("sleeve"), interact::PartState::Placed) << as.events("sleeve", true);
}

}  // namespace
