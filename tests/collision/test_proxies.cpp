// Collision proxies per object (exact primitives for environment objects, optional simplified meshes),
// reported with their measured deviation; the broad phase.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "collision_test_support.hpp"
#include "vaw/primitives.hpp"

using namespace vaw;
using namespace vaw::collision;
using ctest::at;

TEST(Proxies, BundledTableIsAnExactBox) {
  const Assembly a = ctest::loadBundled("sleeve-on-shaft.vaw.json");
  const CollisionWorld w(a);
  const ObjectInfo& table = w.info(ObjectId::environment(0));
  EXPECT_EQ(table.proxy, ProxyKind::Box);
  EXPECT_EQ(table.triangles, 0u);
  EXPECT_EQ(table.displayTriangles, 12u);
  EXPECT_LE(table.deviation, 1e-15);
  EXPECT_NE(table.proxyReason.find("box"), std::string::npos);
  const ObjectInfo& sleeve = w.info(ObjectId::part(*a.findPart("sleeve")));
  EXPECT_EQ(sleeve.proxy, ProxyKind::Mesh);
  EXPECT_EQ(sleeve.triangles, sleeve.displayTriangles);
  EXPECT_EQ(sleeve.cylindricalPatches, 2u);
  EXPECT_GT(sleeve.buildSeconds, 0.0);
  EXPECT_TRUE(w.diagnostics().empty()) << w.diagnostics().front().message();
}

TEST(Proxies, SphereAndCylinderPrimitivesReportTheirTessellationError) {
  ctest::SceneBuilder b;
  b.environment("ball", primitives::sphere(0.1, 32, 16), at(0, 0, 1), "primitive sphere");
  b.environment("post", primitives::cylinder(0.05, 0.5, 32), at(1, 0, 0), "primitive cylinder");
  b.environment("pair", primitives::box({1, 1, 1}), at(3, 0, 0), "compound of 2 primitives");
  const CollisionWorld w(b.a);
  const ObjectInfo& ball = w.info(ObjectId::environment(0));
  EXPECT_EQ(ball.proxy, ProxyKind::Sphere);
  EXPECT_GT(ball.deviation, 1e-4) << "facets lie inside the true sphere";
  EXPECT_LT(ball.deviation, 0.1 * (1.0 - std::cos(std::numbers::pi / 16.0)) * 1.01);
  const ObjectInfo& post = w.info(ObjectId::environment(1));
  EXPECT_EQ(post.proxy, ProxyKind::Cylinder);
  // Largest deviation: the side facets' centroids, at r cos(pi / 32) from the axis.
  EXPECT_NEAR(post.deviation, 0.05 * (1.0 - std::cos(std::numbers::pi / 32.0)), 1e-6);
  EXPECT_EQ(w.info(ObjectId::environment(2)).proxy, ProxyKind::Mesh) << "compounds keep their mesh";
  // The exact sphere: a point 0.1 m from its centre plus 1 mm is 1 mm away.
  ctest::SceneBuilder c = b;
  c.part("probe", primitives::box({0.002, 0.002, 0.002}), at(0, 0, 1.0 + 0.1 + 0.001 + 0.001));
  const CollisionWorld w2(c.a);
  EXPECT_NEAR(w2.distance(ObjectId::part(0), ObjectId::environment(0)), 0.001, 1e-6);
}

TEST(Proxies, PrimitiveThatDoesNotFitItsMeshIsRejected) {
  ctest::SceneBuilder b;
  b.environment("odd", primitives::sphere(0.1, 16, 8), at(0, 0, 0), "primitive box");
  const CollisionWorld w(b.a);
  EXPECT_EQ(w.info(ObjectId::environment(0)).proxy, ProxyKind::Mesh);
  ASSERT_FALSE(w.diagnostics().empty());
  EXPECT_EQ(w.diagnostics().front().field, "collision.proxy-rejected");
}

TEST(Proxies, PrimitivesCanBeTurnedOff) {
  const Assembly a = ctest::loadBundled("sleeve-on-shaft.vaw.json");
  WorldOptions o;
  o.environmentPrimitives = false;
  const CollisionWorld w(a, o);
  EXPECT_EQ(w.info(ObjectId::environment(0)).proxy, ProxyKind::Mesh);
  EXPECT_EQ(w.info(ObjectId::environment(0)).triangles, 12u);
}

TEST(Proxies, SimplifiedMeshIsUsedAndItsDeviationMeasured) {
  const double r = 0.02;
  ctest::SceneBuilder b;
  b.part("fine", primitives::cylinder(r, 0.05, 256), at(0, 0, 0));
  b.part("other", primitives::box({0.01, 0.01, 0.01}), at(0.1, 0, 0));
  WorldOptions o;
  o.simplified.emplace_back(ObjectId::part(0), std::make_shared<const TriMesh>(primitives::cylinder(r, 0.05, 32)));
  const CollisionWorld w(b.a, o);
  const ObjectInfo& fine = w.info(ObjectId::part(0));
  EXPECT_EQ(fine.proxy, ProxyKind::SimplifiedMesh);
  EXPECT_EQ(fine.triangles, 4u * 32u);
  EXPECT_EQ(fine.displayTriangles, 4u * 256u);
  // The 256-gon's vertices midway between the 32-gon's lie r (1 - cos(pi / 32)) outside its facets.
  const double sag = r * (1.0 - std::cos(std::numbers::pi / 32.0));
  EXPECT_NEAR(fine.deviation, sag, 0.02 * sag);
  EXPECT_NE(fine.proxyReason.find("simplified"), std::string::npos);
  EXPECT_EQ(w.collisionMesh(ObjectId::part(0))->triangleCount(), 4u * 32u);
}

TEST(Proxies, BroadPhaseFindsOnlyWhatABoxReachesAndFollowsMovedParts) {
  ctest::SceneBuilder b;
  for (int i = 0; i < 20; ++i) b.part("p" + std::to_string(i), primitives::box({0.01, 0.01, 0.01}), at(0.1 * i, 0, 0));
  CollisionWorld w(b.a);
  Eigen::AlignedBox3d probe(Eigen::Vector3d(0.495, -0.01, -0.01), Eigen::Vector3d(0.505, 0.01, 0.01));
  auto found = w.near(probe);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0], ObjectId::part(5));
  EXPECT_TRUE(w.near(probe, ObjectId::part(5)).empty());
  w.setPose(ObjectId::part(5), at(5.0, 0, 0));
  EXPECT_TRUE(w.near(probe).empty());
  w.setPose(ObjectId::part(7), at(0.5, 0, 0.005));
  found = w.near(probe);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0], ObjectId::part(7));
  EXPECT_NEAR(w.worldBounds(ObjectId::part(7)).min().z(), 0.0, 1e-15);
}

TEST(Proxies, PartsWithTheSameMeshShareOneHierarchy) {
  ctest::SceneBuilder b;
  for (int i = 0; i < 3; ++i) b.part("bolt" + std::to_string(i), primitives::cylinder(0.006, 0.04, 32), at(0.05 * i, 0, 0));
  b.part("other", primitives::cylinder(0.006, 0.041, 32), at(0.2, 0, 0));
  const CollisionWorld w(b.a);
  EXPECT_EQ(w.info(ObjectId::part(0)).proxyReason, "full mesh");
  EXPECT_NE(w.info(ObjectId::part(1)).proxyReason.find("shared with part \"bolt0\""), std::string::npos);
  EXPECT_NE(w.info(ObjectId::part(2)).proxyReason.find("shared"), std::string::npos);
  EXPECT_EQ(w.info(ObjectId::part(3)).proxyReason, "full mesh") << "a different mesh is built on its own";
  EXPECT_EQ(w.patches(ObjectId::part(1)), w.patches(ObjectId::part(0)));
  EXPECT_EQ(w.info(ObjectId::part(2)).cylindricalPatches, 1u);
  // Each copy still collides at its own pose.
  EXPECT_NEAR(w.distance(ObjectId::part(1), ObjectId::part(2)), 0.05 - 0.012, 1e-9);
}

// Rays (the drop line under a lifted part): exact against meshes (the hierarchy finds the triangles, which
// are then intersected) and against box, sphere and cylinder proxies; `except` skips an object.
TEST(Rays, HitMeshesAndPrimitivesExactly) {
  ctest::SceneBuilder b;
  const PartId slab = b.part("slab", primitives::box({0.2, 0.2, 0.05}), at(0, 0, 0.3));
  const PartId probe = b.part("probe", primitives::box({0.01, 0.01, 0.01}), at(0.03, 0.02, 0.5));
  b.environment("table", primitives::box({2, 2, 0.04}), at(0, 0, -0.02), "primitive box");
  b.environment("ball", primitives::sphere(0.1, 32, 16), at(1, 0, 0.1), "primitive sphere");
  b.environment("post", primitives::cylinder(0.05, 0.4, 32), at(-1, 0, 0.2), "primitive cylinder");
  const CollisionWorld w(b.a);
  const Eigen::Vector3d down = -Eigen::Vector3d::UnitZ();
  const auto onSlab = w.castRay({0.03, 0.02, 0.5}, down, 10.0, ObjectId::part(probe));
  ASSERT_TRUE(onSlab);
  EXPECT_EQ(onSlab->object, ObjectId::part(slab));
  EXPECT_NEAR(onSlab->point.z(), 0.325, 1e-12);
  EXPECT_NEAR(onSlab->distance, 0.175, 1e-12);
  const auto self = w.castRay({0.03, 0.02, 0.6}, down, 10.0);
  ASSERT_TRUE(self);
  EXPECT_EQ(self->object, ObjectId::part(probe)) << "without except the probe itself is first";
  const auto table = w.castRay({0.5, 0.5, 1.0}, down, 10.0);
  ASSERT_TRUE(table);
  EXPECT_EQ(table->object, ObjectId::environment(0));
  EXPECT_NEAR(table->point.z(), 0.0, 1e-12);
  const auto ball = w.castRay({1.0, 0.0, 1.0}, down, 10.0);
  ASSERT_TRUE(ball);
  EXPECT_NEAR(ball->point.z(), 0.2, 1e-12) << "the exact sphere, not its facets";
  const auto post = w.castRay({-1.03, 0.0, 1.0}, down, 10.0);
  ASSERT_TRUE(post);
  EXPECT_NEAR(post->point.z(), 0.4, 1e-12);
  const auto side = w.castRay({-2.0, 0.0, 0.2}, Eigen::Vector3d::UnitX(), 10.0);
  ASSERT_TRUE(side);
  EXPECT_NEAR(side->point.x(), -1.05, 1e-12) << "the cylinder's side";
  EXPECT_FALSE(w.castRay({5.0, 5.0, 1.0}, down, 10.0)) << "nothing below";
  EXPECT_FALSE(w.castRay({0.5, 0.5, 1.0}, down, 0.5)) << "the table is farther than the ray";
}

namespace {

// A 20 mm cube at the origin and a 10 mm cylinder (64 facets) standing 0.1 m along x: the cube's face at
// x = 0.01 is 80 mm from the cylinder's side.
ctest::SceneBuilder cubeAndCylinder() {
  ctest::SceneBuilder b;
  b.part("a", primitives::box({0.02, 0.02, 0.02}), at(0, 0, 0));
  b.part("b", primitives::cylinder(0.01, 0.04, 64), at(0.1, 0.003, 0));
  return b;
}

// A pair of surface points of that scene far from the nearest: the cube's far face, the cylinder's far side.
CollisionWorld::Nearest farSides() {
  CollisionWorld::Nearest far;
  far.onA = Eigen::Vector3d(-0.01, 0.0, 0.0);
  far.onB = Eigen::Vector3d(0.11, 0.003, 0.0);
  return far;
}

}  // namespace

// The nearest points of two meshes, in the world: exact, and the same when the search is bounded by a pair
// of surface points (the clearance along a path hands it the last step's pair, docs/clearance.md); a bound
// that is the nearest pair itself comes back as it is.
TEST(Proxies, NearestPointsAreExactWithOrWithoutABound) {
  const ctest::SceneBuilder b = cubeAndCylinder();
  CollisionWorld w(b.a);
  const ObjectId a = ObjectId::part(0), c = ObjectId::part(1);
  const CollisionWorld::Nearest free = w.nearest(a, c);
  // The box's face at x = 0.01; the cylinder's facets within 1.2e-5 m of its radius at x = 0.09.
  EXPECT_NEAR(free.distance, 0.08, 2e-5);
  EXPECT_NEAR(free.onA.x(), 0.01, 1e-9);
  EXPECT_NEAR((free.onA - free.onB).norm(), free.distance, 1e-12);
  const CollisionWorld::Nearest far = farSides();
  const CollisionWorld::Nearest bounded = w.nearest(a, c, &far);
  EXPECT_NEAR(bounded.distance, free.distance, 1e-15);
  // Many pairs are nearest (an edge of the cylinder along the box's face): any of them, truly that far.
  EXPECT_NEAR(bounded.onA.x(), 0.01, 1e-9);
  EXPECT_NEAR((bounded.onA - bounded.onB).norm(), bounded.distance, 1e-12);
  const CollisionWorld::Nearest again = w.nearest(a, c, &free);
  EXPECT_NEAR(again.distance, free.distance, 1e-15);
  // Moved 30 mm closer: the old pair, carried along, bounds the new answer.
  w.setPose(c, at(0.07, 0.003, 0));
  CollisionWorld::Nearest carried = free;
  carried.onB.x() -= 0.03;
  EXPECT_NEAR(w.nearest(a, c, &carried).distance, w.nearest(a, c).distance, 1e-15);
  EXPECT_NEAR(w.nearest(a, c).distance, free.distance - 0.03, 1e-12);
}

// A caller that needs no distance from some bound on (the clearance of an object that can change nothing
// there) gets the bound back, marked beyond, with or without a pair to seed the search; under the bound
// it gets the exact answer, as without one.
TEST(Proxies, NearestStopsAtTheDistanceItIsToldNotToLookBeyond) {
  const ctest::SceneBuilder b = cubeAndCylinder();
  CollisionWorld w(b.a);
  const ObjectId a = ObjectId::part(0), c = ObjectId::part(1);
  const CollisionWorld::Nearest exact = w.nearest(a, c);
  ASSERT_FALSE(exact.beyond);
  const CollisionWorld::Nearest cut = w.nearest(a, c, nullptr, 0.05);
  EXPECT_TRUE(cut.beyond);
  EXPECT_EQ(cut.distance, 0.05);
  const CollisionWorld::Nearest far = farSides();
  const CollisionWorld::Nearest seededCut = w.nearest(a, c, &far, 0.079);
  EXPECT_TRUE(seededCut.beyond) << "0.079 m is under the true 0.08 m";
  EXPECT_EQ(seededCut.distance, 0.079);
  const CollisionWorld::Nearest under = w.nearest(a, c, &far, 0.081);
  EXPECT_FALSE(under.beyond);
  EXPECT_NEAR(under.distance, exact.distance, 1e-15);
  EXPECT_NEAR((under.onA - under.onB).norm(), under.distance, 1e-12);
}

// Thin parts face to face, the case the hierarchy's split rule is for (docs/collision.md, "Hierarchies"):
// a 60 mm disc 6 mm thick above a 100 mm one, tilted, turned and shifted about. Over the lower disc's flat
// top (z = 3 mm), the distance is the height of the upper disc's lowest vertex above it.
TEST(Proxies, ThinDiscsFaceToFaceMeasureExactly) {
  ctest::SceneBuilder b;
  b.part("lower", primitives::cylinder(0.05, 0.006, 96), at(0, 0, 0));
  b.part("upper", primitives::cylinder(0.03, 0.006, 96), at(0, 0, 0.03));
  CollisionWorld w(b.a);
  const ObjectId lower = ObjectId::part(0), upper = ObjectId::part(1);
  const TriMesh& disc = *b.a.parts[1].mesh;
  for (int k = 0; k < 12; ++k) {
    Eigen::Isometry3d pose = at(0.0025 * k - 0.014, 0.001 * k - 0.006, 0.01 + 0.002 * k);
    pose.rotate(Eigen::AngleAxisd(0.01 * k, Eigen::Vector3d(1, 2, 0).normalized()));
    pose.rotate(Eigen::AngleAxisd(0.3 * k, Eigen::Vector3d::UnitZ()));
    w.setPose(upper, pose);
    double lowest = std::numeric_limits<double>::infinity();
    for (const Eigen::Vector3d& v : disc.vertices) lowest = std::min(lowest, (pose * v).z());
    const CollisionWorld::Nearest n = w.nearest(lower, upper);
    EXPECT_NEAR(n.distance, lowest - 0.003, 1e-12) << "pose " << k;
    EXPECT_NEAR(n.onA.z(), 0.003, 1e-12) << "on the lower disc's top, pose " << k;
  }
}
