// Clearance fits: a bore larger than its shaft is an insert support with that radial clearance, the part
// may rest anywhere in its play without being blocked or losing touch, and only a bore smaller than the
// shaft (interference) is refused, with both radii named. Geometry: a 15 mm shaft (64 segments) and a
// 40 mm brass-like sleeve (outer radius 25 mm) whose bore is 15 mm + clearance.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "collision_test_support.hpp"
#include "vaw/primitives.hpp"

using namespace vaw;
using namespace vaw::collision;
using ctest::at;

namespace {

constexpr double kShaft = 0.015;

Assembly shaftAndSleeve(double clearance) {
  ctest::SceneBuilder b;
  b.part("shaft", primitives::cylinder(kShaft, 0.2, 64), at(0, 0, 0.1));
  b.part("sleeve", primitives::tube(0.025, kShaft + clearance, 0.04, 64), at(0, 0, 0.1));
  b.base(0);
  b.insert(1, {0, 0, 0}, {0, 0, 1}, {0, 0, 0}, {0, 0, 1});
  return b.a;
}

// The sleeve's pose with its axis `offset` off the shaft's, towards the angle `towards` (rad about z).
Eigen::Isometry3d inPlay(double offset, double towards, double z = 0.1) {
  return at(offset * std::cos(towards), offset * std::sin(towards), z);
}

}  // namespace

TEST(ClearanceFit, ABoreLargerThanTheShaftIsAFitWithItsClearance) {
  // Before: any bore more than 0.05 mm larger than the shaft was "no equal-diameter bore and shaft pair".
  for (const double clearance : {0.0, 1e-6, 1e-5, 5e-5, 1e-4, 1e-3}) {
    const Assembly a = shaftAndSleeve(clearance);
    const CollisionWorld w(a);
    const Support s = w.support(a.constraints[0]);
    ASSERT_TRUE(s.problem.empty()) << clearance << ": " << s.problem;
    EXPECT_NEAR(s.clearance, clearance, 1e-12);
    EXPECT_NEAR(s.partRadius, kShaft + clearance, 1e-12);
    EXPECT_NEAR(s.baseRadius, kShaft, 1e-12);
    ASSERT_EQ(s.fitPairs.size(), 1u);
    // The same matching without a collision world, and in the part inspector's data.
    const auto fits = constraintFits(a);
    ASSERT_EQ(fits.size(), 1u);
    EXPECT_NEAR(fits[0].support.clearance, clearance, 1e-12);
    EXPECT_EQ(w.info(ObjectId::part(1)).fit, fits[0].text);
    EXPECT_NE(fits[0].text.find("clearance"), std::string::npos) << fits[0].text;
  }
  const Support s = CollisionWorld(shaftAndSleeve(5e-5)).support(shaftAndSleeve(5e-5).constraints[0]);
  EXPECT_EQ(describeFit(s), "insert: the part's bore (r = 15.05 mm) on the base's shaft (r = 15 mm), clearance 0.05 mm");
}

TEST(ClearanceFit, ThePartRestsAnywhereInItsPlayWithoutBeingBlocked) {
  for (const double clearance : {1e-6, 5e-5, 1e-3}) {
    const Assembly a = shaftAndSleeve(clearance);
    const CollisionWorld w(a);
    const Support s = w.support(a.constraints[0]);
    ASSERT_TRUE(s.problem.empty()) << s.problem;
    // Against the shaft on any side: towards a facet's corner, a facet's middle, and in between.
    for (const double towards : {0.0, M_PI / 64.0, 0.3, 2.0, 4.0}) {
      const Eigen::Isometry3d pose = inPlay(clearance, towards);
      const TouchResult t = w.touching(s, pose);
      EXPECT_TRUE(t.touching) << clearance << " towards " << towards << ": " << t.reason;
      EXPECT_NEAR(t.separation, clearance, 1e-12);
      const BlockResult b = w.blocked(s, pose);
      EXPECT_FALSE(b.blocked) << "clearance " << clearance << " towards " << towards << ": the bore on its shaft is the fit";
    }
    // Farther off than the play: not on the shaft any more.
    const TouchResult off = w.touching(s, inPlay(clearance + 1e-4, 0.3));
    EXPECT_FALSE(off.touching);
    EXPECT_EQ(off.reason, "the part's axis is off the base's axis");
  }
}

TEST(ClearanceFit, AnObstacleIsStillSeenInThePlay) {
  // The sleeve resting in its 1 mm play, lowered onto a collar (a 40 mm disc around the shaft at z = 50 mm):
  // the clearance hides only the bore on the shaft, not the collar under the sleeve's end face.
  ctest::SceneBuilder b;
  TriMesh base = primitives::cylinder(kShaft, 0.2, 64);
  for (auto& v : base.vertices) v.z() += 0.1;
  TriMesh collar = primitives::tube(0.04, kShaft, 0.01, 64);
  for (auto& v : collar.vertices) v.z() += 0.045;
  base.append(collar);
  b.part("shaft", base, at(0, 0, 0));
  b.part("sleeve", primitives::tube(0.025, kShaft + 1e-3, 0.04, 64), at(0, 0, 0.1));
  b.base(0);
  b.insert(1, {0, 0, 0}, {0, 0, 1}, {0, 0, 0}, {0, 0, 1});
  const CollisionWorld w(b.a);
  const Support s = w.support(b.a.constraints[0]);
  ASSERT_TRUE(s.problem.empty()) << s.problem;
  EXPECT_NEAR(s.clearance, 1e-3, 1e-12);
  EXPECT_FALSE(w.blocked(s, inPlay(1e-3, 0.3, 0.1)).blocked) << "30 mm above the collar";
  const BlockResult sunk = w.blocked(s, inPlay(1e-3, 0.3, 0.069));  // its end face 1 mm into the collar
  EXPECT_TRUE(sunk.blocked);
}

TEST(ClearanceFit, OnlyInterferenceIsRefusedWithTheNumbers) {
  // A bore 0.1 mm smaller than the shaft; and within the radius tolerance (0.05 mm) still a fit, clearance 0.
  const Support tight = CollisionWorld(shaftAndSleeve(-1e-4)).support(shaftAndSleeve(-1e-4).constraints[0]);
  EXPECT_EQ(tight.problem,
            "interference: the part's bore (r = 14.9 mm) is 0.1 mm smaller than the base's shaft (r = 15 mm); a bore fits a "
            "shaft when it is at least as large (to within 0.05 mm)");
  EXPECT_TRUE(tight.fitPairs.empty());
  EXPECT_EQ(describeFit(tight).rfind("insert: interference", 0), 0u);
  const Support rounded = CollisionWorld(shaftAndSleeve(-4e-5)).support(shaftAndSleeve(-4e-5).constraints[0]);
  EXPECT_TRUE(rounded.problem.empty()) << rounded.problem;
  EXPECT_EQ(rounded.clearance, 0.0);
}

TEST(ClearanceFit, ThePinInAHoleIsAFitToo) {
  // The roles turned: the part is the shaft (a 10 mm pin), the base has the bore (10.2 mm, 0.2 mm play).
  ctest::SceneBuilder b;
  b.part("block", primitives::tube(0.05, 0.0102, 0.04, 64), at(0, 0, 0.02));
  b.part("pin", primitives::cylinder(0.01, 0.08, 64), at(0, 0, 0.05));
  b.base(0);
  b.insert(1, {0, 0, 0}, {0, 0, 1}, {0, 0, 0}, {0, 0, 1});
  const CollisionWorld w(b.a);
  const Support s = w.support(b.a.constraints[0]);
  ASSERT_TRUE(s.problem.empty()) << s.problem;
  EXPECT_NEAR(s.clearance, 2e-4, 1e-12);
  EXPECT_EQ(describeFit(s), "insert: the part's shaft (r = 10 mm) in the base's bore (r = 10.2 mm), clearance 0.2 mm");
  EXPECT_TRUE(w.touching(s, inPlay(2e-4, 1.0, 0.05)).touching);
  EXPECT_FALSE(w.blocked(s, inPlay(2e-4, 1.0, 0.05)).blocked);
}
