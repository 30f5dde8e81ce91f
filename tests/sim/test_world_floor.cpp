// The room's floor (docs/physics.md, "The floor"): a scene that declares none gets one 0.72 m below its
// table's top; a part thrown or dropped off the table comes to rest on it, STATIC "on the floor", and is
// picked up again from there. A part released over the base's edge still lands on the table.
#include <gtest/gtest.h>

#include "sim_test_support.hpp"
#include "vaw/primitives.hpp"
#include "vaw/sim/scene.hpp"

namespace vaw {
namespace {

using interact::PartState;
using simtest::at;
using sim::Input;
using sim::World;

Eigen::AlignedBox3d tableBox(const Assembly& a) {
  Eigen::AlignedBox3d table;
  for (const auto& e : a.environment)
    if (e.kind == "table") table = Eigen::AlignedBox3d(e.pose * e.mesh->bounds().min(), e.pose * e.mesh->bounds().max());
  return table;
}
double tableTop(const Assembly& a) { return tableBox(a).max().z(); }

double lowestZ(const World& w, PartId id) {
  double low = 1e9;
  for (const auto& v : w.scene()->assembly().parts[id].mesh->vertices) low = std::min(low, (w.part(id).pose * v).z());
  return low;
}

std::string floorCause(const World& w, PartId id) {
  for (const auto& t : w.transitions())
    if (t.part == id && t.cause.find("on the floor") != std::string::npos) return t.cause;
  return {};
}

// Grabs `id` at its centre of mass, lifts it by `lift` over half a second and lets go with the hand moving at
// `velocity` (as a tracker measures it).
void throwPart(World& w, PartId id, const Eigen::Vector3d& lift, const Eigen::Vector3d& velocity) {
  const Part& p = w.scene()->assembly().parts[id];
  const Eigen::Vector3d com = w.part(id).pose * p.mass.centerOfMass;
  Input in;
  const int steps = static_cast<int>(0.5 / w.settings().step());
  for (int k = 0; k <= steps; ++k) {
    in.right = simtest::hand(at(com.x(), com.y(), com.z()), true);
    in.right.pose.translation() += lift * (static_cast<double>(k) / steps);
    w.step(in);
  }
  ASSERT_EQ(w.part(id).state, PartState::InHand);
  in.right.grab = false;
  in.right.velocity = interact::Twist{velocity, Eigen::Vector3d::Zero()};
  w.step(in);
}

TEST(WorldFloor, AssumedFloorLiesADesksHeightBelowTheTableAndIsNotInTheHash) {
  const Assembly a = simtest::loadBundled("large-gearbox.vaw.json");
  const auto scene = sim::Scene::build(a);
  const Assembly& s = scene->assembly();
  ASSERT_EQ(s.environment.size(), a.environment.size() + 1);
  const EnvironmentObject& floor = s.environment.back();
  EXPECT_EQ(floor.kind, "floor");
  EXPECT_TRUE(floor.implied);
  EXPECT_NEAR((floor.pose * floor.mesh->bounds().max()).z(), tableTop(a) - sim::kDefaultFloorDepth, 1e-12);
  EXPECT_EQ(s.tree.children.back().name, "floor") << "the scene tree shows it";
  // The floor is not hashed (recorded sessions still match), and building again adds no second one.
  EXPECT_EQ(sim::Scene::build(s)->contentHash(), scene->contentHash());
  EXPECT_EQ(sim::Scene::build(s)->assembly().environment.size(), s.environment.size());
}

TEST(WorldFloor, ADeclaredFloorIsTheOnlyOne) {
  Assembly a = simtest::loadBundled("sleeve-on-shaft.vaw.json");
  EnvironmentObject floor;
  floor.name = "lab floor";
  floor.kind = "floor";
  floor.mesh = std::make_shared<const TriMesh>(primitives::box({4, 4, 0.1}));
  floor.pose.translation() = Eigen::Vector3d(0, 0, -1.05);
  a.environment.push_back(floor);
  const auto scene = sim::Scene::build(a);
  ASSERT_EQ(scene->assembly().environment.size(), a.environment.size());
  EXPECT_EQ(scene->assembly().environment.back().name, "lab floor");
}

TEST(WorldFloor, ABoltThrownOffTheTableComesToRestOnTheFloor) {
  const Assembly a = simtest::loadBundled("large-gearbox.vaw.json");
  World w(a);
  const PartId bolt = *a.findPart("bolt-14");
  // Lifted clear of the gearbox and thrown at 2.8 m/s away from the table's centre.
  const Eigen::AlignedBox3d table = tableBox(a);
  Eigen::Vector3d away = w.part(bolt).pose.translation() - table.center();
  away.z() = 0.0;
  throwPart(w, bolt, {0, 0, 0.25}, 2.8 * away.normalized());
  ASSERT_EQ(w.part(bolt).state, PartState::InSpace);
  const double release = w.time();
  while (w.time() < release + 3.0 && w.part(bolt).state == PartState::InSpace) w.step(Input{});
  ASSERT_EQ(w.part(bolt).state, PartState::Static) << "still flying 3 s after the throw, at z " << lowestZ(w, bolt);
  EXPECT_LT(w.time() - release, 3.0);
  EXPECT_NEAR(lowestZ(w, bolt), tableTop(a) - sim::kDefaultFloorDepth, 1e-3) << "resting on the floor, within the contact tolerance";
  EXPECT_FALSE(floorCause(w, bolt).empty()) << "the transition says where it came to rest: " << w.transitions().back().cause;
  RecordProperty("flight_s", simtest::num(w.time() - release));
}

TEST(WorldFloor, APartDroppedBesideTheTableLandsOnTheFloorAndIsPickedUpAgain) {
  const Assembly a = simtest::loadBundled("sleeve-on-shaft.vaw.json");
  World w(a);
  const PartId sleeve = *a.findPart("sleeve");
  const Eigen::AlignedBox3d table = tableBox(a);
  const Eigen::Vector3d com = w.part(sleeve).pose * a.parts[sleeve].mass.centerOfMass;
  // Carried 10 cm past the table's edge, held still, let go.
  const Eigen::Vector3d beside(table.max().x() + 0.1, com.y(), table.max().z() + 0.1);
  throwPart(w, sleeve, beside - com, Eigen::Vector3d::Zero());
  for (int k = 0; k < 400 && w.part(sleeve).state == PartState::InSpace; ++k) w.step(Input{});
  ASSERT_EQ(w.part(sleeve).state, PartState::Static);
  EXPECT_NEAR(lowestZ(w, sleeve), table.max().z() - sim::kDefaultFloorDepth, 1e-3);
  EXPECT_FALSE(floorCause(w, sleeve).empty());

  // Picked up from the floor and put down over the table: it lands on the table.
  const Eigen::Vector3d onFloor = w.part(sleeve).pose * a.parts[sleeve].mass.centerOfMass;
  const Eigen::Vector3d overTable(table.center().x() + 0.25 * table.sizes().x(), table.center().y() - 0.25 * table.sizes().y(),
                                  table.max().z() + 0.05);
  throwPart(w, sleeve, overTable - onFloor, Eigen::Vector3d::Zero());
  for (int k = 0; k < 400 && w.part(sleeve).state == PartState::InSpace; ++k) w.step(Input{});
  EXPECT_EQ(w.part(sleeve).state, PartState::Static);
  EXPECT_NEAR(lowestZ(w, sleeve), table.max().z(), 1e-3) << "on the table again";
  EXPECT_NE(w.transitions().back().cause.find("hit table"), std::string::npos) << w.transitions().back().cause;
}

}  // namespace
}  // namespace vaw
