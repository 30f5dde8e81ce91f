// Surface patch classification: planar and cylindrical patches, their fits and tolerances.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "collision_test_support.hpp"
#include "vaw/collision/surface_patches.hpp"
#include "vaw/primitives.hpp"

using namespace vaw;
using namespace vaw::collision;

namespace {
constexpr double kPi = std::numbers::pi;

int countConvex(const SurfacePatches& sp, bool convex) {
  int n = 0;
  for (const auto& c : sp.cylinders) n += c.convex == convex ? 1 : 0;
  return n;
}
}  // namespace

TEST(Patches, BoxHasSixFacesAndNoCylinder) {
  const SurfacePatches sp = classifySurfaces(primitives::box({0.06, 0.04, 0.03}));
  ASSERT_EQ(sp.planes.size(), 6u);
  EXPECT_TRUE(sp.cylinders.empty());
  EXPECT_EQ(sp.degenerateTriangles, 0u);
  EXPECT_EQ(sp.boundaryEdges, 0u);
  for (const auto& p : sp.planes) {
    EXPECT_EQ(p.triangles.size(), 2u);
    EXPECT_LE(p.residual, 1e-15);
    ASSERT_EQ(p.outline.size(), 1u);
    EXPECT_EQ(p.outline[0].size(), 4u);  // the split diagonal is inside the patch
    EXPECT_EQ(p.hull.size(), 4u);
  }
  // The bottom face: normal -z, area 0.06 x 0.04.
  bool bottom = false;
  for (const auto& p : sp.planes)
    if (p.normal.z() < -0.999999) {
      bottom = true;
      EXPECT_NEAR(p.area, 0.06 * 0.04, 1e-15);
      EXPECT_NEAR(p.offset(), 0.015, 1e-15);
    }
  EXPECT_TRUE(bottom);
}

TEST(Patches, FinelySplitFaceIsOnePatchWithAFourCornerOutline) {
  const SurfacePatches sp = classifySurfaces(primitives::gridBox({0.3, 0.2, 0.04}, 20));
  ASSERT_EQ(sp.planes.size(), 6u);
  for (const auto& p : sp.planes) {
    EXPECT_EQ(p.triangles.size(), 800u);
    ASSERT_EQ(p.outline.size(), 1u);
    EXPECT_EQ(p.outline[0].size(), 4u) << "collinear boundary vertices are merged";
  }
}

TEST(Patches, CylinderIsFoundWithItsRadiusAxisAndSagitta) {
  const double r = 0.015, h = 0.12;
  const int n = 64;
  const SurfacePatches sp = classifySurfaces(primitives::cylinder(r, h, n));
  ASSERT_EQ(sp.cylinders.size(), 1u);
  const CylindricalPatch& c = sp.cylinders[0];
  EXPECT_TRUE(c.convex);
  EXPECT_NEAR(c.radius, r, 1e-12);
  EXPECT_NEAR(std::abs(c.direction.z()), 1.0, 1e-12);
  EXPECT_NEAR(c.length, h, 1e-12);
  EXPECT_NEAR(std::hypot(c.point.x(), c.point.y()), 0.0, 1e-12);
  EXPECT_NEAR(c.sagitta, r * (1.0 - std::cos(kPi / n)), 1e-12);
  EXPECT_NEAR(c.coverage, 2.0 * kPi, 1e-9);
  EXPECT_EQ(c.facets.size(), static_cast<std::size_t>(n));
  EXPECT_EQ(c.triangles.size(), static_cast<std::size_t>(2 * n));
  // Caps stay planar patches; every side triangle is in the cylinder.
  EXPECT_EQ(sp.planes.size(), static_cast<std::size_t>(n + 2));
  std::size_t inCylinder = 0;
  for (int c0 : sp.cylinderOf) inCylinder += c0 >= 0 ? 1 : 0;
  EXPECT_EQ(inCylinder, static_cast<std::size_t>(2 * n));
}

TEST(Patches, TubeHasAConvexOutsideAndAConcaveBore) {
  const SurfacePatches sp = classifySurfaces(primitives::tube(0.025, 0.015, 0.04, 64));
  ASSERT_EQ(sp.cylinders.size(), 2u);
  EXPECT_EQ(countConvex(sp, true), 1);
  EXPECT_EQ(countConvex(sp, false), 1);
  for (const auto& c : sp.cylinders) EXPECT_NEAR(c.radius, c.convex ? 0.025 : 0.015, 1e-12);
}

TEST(Patches, PrismsWithFewSidesAreNotCylinders) {
  // A hexagon turns 60 degrees per facet, more than maxFacetTurn (0.5 rad): six planar sides.
  EXPECT_TRUE(classifySurfaces(primitives::cylinder(0.01, 0.02, 6)).cylinders.empty());
  EXPECT_TRUE(classifySurfaces(primitives::cylinder(0.01, 0.02, 12)).cylinders.empty());
  EXPECT_EQ(classifySurfaces(primitives::cylinder(0.01, 0.02, 13)).cylinders.size(), 1u);
}

TEST(Patches, SphereHasNoCylinder) {
  const SurfacePatches sp = classifySurfaces(primitives::sphere(0.02, 32, 16));
  EXPECT_TRUE(sp.cylinders.empty());
  EXPECT_GT(sp.planes.size(), 100u);
}

TEST(Patches, BundledSleeveAndShaftFitEachOther) {
  const Assembly a = ctest::loadBundled("sleeve-on-shaft.vaw.json");
  const SurfacePatches base = classifySurfaces(*a.parts[*a.base].mesh);
  const SurfacePatches sleeve = classifySurfaces(*a.parts[*a.findPart("sleeve")].mesh);
  // Base: the shaft (r 15 mm, from the block's top at 40 mm to the chamfer at 159 mm).
  ASSERT_EQ(base.cylinders.size(), 1u);
  EXPECT_TRUE(base.cylinders[0].convex);
  EXPECT_NEAR(base.cylinders[0].radius, 0.015, 1e-9);
  EXPECT_NEAR(base.cylinders[0].point.z(), 0.040, 1e-9);
  EXPECT_NEAR(base.cylinders[0].length, 0.119, 1e-9);
  // Sleeve: bore r 15 mm (concave) and outside r 25 mm (convex), 40 mm long.
  ASSERT_EQ(sleeve.cylinders.size(), 2u);
  ASSERT_EQ(countConvex(sleeve, false), 1);
  for (const auto& c : sleeve.cylinders) {
    EXPECT_NEAR(c.radius, c.convex ? 0.025 : 0.015, 1e-9);
    EXPECT_NEAR(c.length, 0.040, 1e-9);
  }
}

TEST(Patches, BundledPlateTopIsOnePatchOverItsGrid) {
  const Assembly a = ctest::loadBundled("block-on-plate.vaw.json");
  const SurfacePatches sp = classifySurfaces(*a.parts[*a.base].mesh);
  int tops = 0;
  for (const auto& p : sp.planes)
    if (p.normal.z() > 0.999999) {
      ++tops;
      EXPECT_EQ(p.triangles.size(), 48u);  // the 6 x 4 grid
      EXPECT_NEAR(p.area, 0.3 * 0.2, 1e-12);
      ASSERT_EQ(p.outline.size(), 1u);
      EXPECT_EQ(p.outline[0].size(), 4u);
    }
  EXPECT_EQ(tops, 1);
}
