// FreeMotion: around a part on its support, the motions that can meet nothing. What it claims is checked
// against the two exact checks it lets the world skip: at poses spread over the claimed motions the part is
// touching and not blocked; just beyond a bound it calls an obstacle the part is blocked within a
// tolerance and a half, and just beyond a bound it calls the end of the touch the touch is lost within
// two tolerances and a half. Tolerances::distance = 10 um.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "collision_test_support.hpp"
#include "vaw/primitives.hpp"

using namespace vaw;
using namespace vaw::collision;
using ctest::at;

namespace {

constexpr double kMotionTol = 1e-5;

Eigen::Isometry3d turnedAbout(const Eigen::Vector3d& axis, double angle) {
  Eigen::Isometry3d r = Eigen::Isometry3d::Identity();
  r.linear() = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  return r;
}

// The base turned by `deg` about world x through a point 0.3 m up.
Eigen::Isometry3d tilted(double deg) {
  Eigen::Isometry3d r = turnedAbout(Eigen::Vector3d::UnitX(), deg * std::numbers::pi / 180.0);
  const Eigen::Vector3d pivot(0, 0, 0.3);
  r.translation() = pivot - r.linear() * pivot;
  return r;
}

// Checks the claim of an axis FreeMotion found for the part at `inBase` (base frame): every slide within it,
// at any turn, touches and is not blocked. Returns the number of poses checked.
int checkAxisClaim(const CollisionWorld& w, const Support& s, const Eigen::Isometry3d& base, const Eigen::Isometry3d& inBase,
                   const FreeMotion& f, const Eigen::Vector3d& axisInBase) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int n = 0;
  for (int k = 0; k <= 40; ++k) {
    const double d = k == 0 ? f.axialMin : k == 40 ? f.axialMax : f.axialMin + u(rng) * (f.axialMax - f.axialMin);
    Eigen::Isometry3d p = inBase;
    p.pretranslate(d * axisInBase);
    // A turn about the part's own axis, which lies along axisInBase through its axis point.
    const Eigen::Vector3d pivot = p * s.partAxis.point;
    Eigen::Isometry3d turn = turnedAbout(axisInBase, 2.0 * std::numbers::pi * u(rng));
    turn.translation() = pivot - turn.linear() * pivot;
    const Eigen::Isometry3d pose = base * turn * p;
    EXPECT_TRUE(w.touching(s, pose).touching) << "slide " << d << ": " << w.touching(s, pose).reason;
    EXPECT_FALSE(w.blocked(s, pose).blocked) << "slide " << d;
    ++n;
  }
  return n;
}

}  // namespace

TEST(FreeMotion, SleeveOnItsShaftFreeBetweenTheBlockAndTheShaftsEnd) {
  Assembly a = ctest::loadBundled("sleeve-on-shaft.vaw.json");
  const PartId sleeve = *a.findPart("sleeve");
  for (const double tilt : {0.0, 30.0, 105.0}) {
    a.parts[*a.base].pose = tilted(tilt);
    const CollisionWorld w(a);
    const Support s = w.support(a.constraints[0]);
    ASSERT_TRUE(s.problem.empty()) << s.problem;
    const Eigen::Isometry3d inBase = at(0, 0, 0.08);  // the sleeve's bottom 40 mm above the block
    const FreeMotion f = w.freeMotion(s, tilted(tilt) * inBase);
    // Down to the block's top face (half a tolerance into it); up to where the shaft's chamfer and cap
    // begin (the sleeve's top at 159 mm), which lie within its band.
    EXPECT_NEAR(f.axialMin, -0.04 - 0.5 * kMotionTol, 1e-9) << tilt;
    EXPECT_EQ(f.atMin, FreeMotion::Bound::Obstacle);
    EXPECT_NEAR(f.axialMax, 0.159 - 0.12 + 0.5 * kMotionTol, 1e-6) << tilt;
    EXPECT_EQ(f.atMax, FreeMotion::Bound::Obstacle);
    checkAxisClaim(w, s, tilted(tilt), inBase, f, Eigen::Vector3d::UnitZ());
    // A tolerance beyond the block's bound, the sleeve's end face is blocked by the block's top face.
    EXPECT_TRUE(w.blocked(s, tilted(tilt) * at(0, 0, 0.08 + f.axialMin - kMotionTol)).blocked);
  }
  // Resting on the block, inside its face's span, nothing is claimed (the exact checks decide until the
  // sleeve has left it); a tolerance above it, the way down is free to the face and the way up as before.
  a.parts[*a.base].pose = Eigen::Isometry3d::Identity();
  const CollisionWorld w(a);
  const Support s = w.support(a.constraints[0]);
  const FreeMotion resting = w.freeMotion(s, at(0, 0, 0.04 - 0.5 * kMotionTol));
  EXPECT_EQ(resting.axialMin, 0.0);
  EXPECT_EQ(resting.axialMax, 0.0);
  const FreeMotion above = w.freeMotion(s, at(0, 0, 0.04 + kMotionTol));
  EXPECT_NEAR(above.axialMin, -1.5 * kMotionTol, 1e-12);
  EXPECT_NEAR(above.axialMax, 0.159 - 0.08 - kMotionTol + 0.5 * kMotionTol, 1e-6);
  (void)sleeve;
}

TEST(FreeMotion, InItsPlayOnABareShaftItIsFreeBetweenTheCaps) {
  // A bare shaft 200 mm long and a sleeve in a 1 mm play: the shaft's caps lie within the bore's band, so
  // they bound the free motion (conservatively: the bore passes them, the sleeve's touch lasts until the
  // bore has left the shaft); within it every pose in the play touches and is free.
  ctest::SceneBuilder b;
  b.part("shaft", primitives::cylinder(0.015, 0.2, 64), at(0, 0, 0.1));
  b.part("sleeve", primitives::tube(0.025, 0.016, 0.04, 64), at(0.001, 0, 0.1));
  b.base(0);
  b.insert(1, {0, 0, 0}, {0, 0, 1}, {0, 0, 0}, {0, 0, 1});
  const CollisionWorld w(b.a);
  const Support s = w.support(b.a.constraints[0]);
  ASSERT_TRUE(s.problem.empty()) << s.problem;
  const FreeMotion f = w.freeMotion(s, at(0.001, 0, 0.1));
  // The sleeve spans z = 80..120 mm; the caps are at z = 0 and 200 mm.
  EXPECT_NEAR(f.axialMin, -0.08 - 0.5 * kMotionTol, 1e-9);
  EXPECT_NEAR(f.axialMax, 0.08 + 0.5 * kMotionTol, 1e-9);
  checkAxisClaim(w, s, Eigen::Isometry3d::Identity(), at(0.001, 0, 0.1), f, Eigen::Vector3d::UnitZ());
  // Beyond its play the sleeve is off the shaft: nothing is claimed.
  const FreeMotion off = w.freeMotion(s, at(0.0011, 0, 0.1));
  EXPECT_EQ(off.axialMin, 0.0);
  EXPECT_EQ(off.axialMax, 0.0);
}

TEST(FreeMotion, GearTurnsAllAroundAndSlidesUpToThePost) {
  Assembly a = ctest::loadBundled("gear-on-shaft.vaw.json");
  const PartId gear = *a.findPart("gear");
  const CollisionWorld w(a);
  const Support s = w.support(a.constraints[0]);
  ASSERT_TRUE(s.problem.empty()) << s.problem;
  // The gear 30 mm along the shaft from its place (x = 90 mm), turned a quarter turn about it.
  const Eigen::Isometry3d start = at(0.03, 0, 0) * *a.parts[gear].finalPose;
  const FreeMotion f = w.freeMotion(s, start);
  // Towards the post (its face at x = -120 mm) and the shaft's free end (x = 130 mm), less the gear's own
  // half width: both obstacles in the band of its teeth.
  EXPECT_LT(f.axialMin, -0.15);
  EXPECT_GT(f.axialMax, 0.02);
  EXPECT_EQ(f.atMin, FreeMotion::Bound::Obstacle);
  checkAxisClaim(w, s, Eigen::Isometry3d::Identity(), start, f, Eigen::Vector3d::UnitX());
  EXPECT_TRUE(w.blocked(s, at(f.axialMin - 5e-4, 0, 0) * start).blocked) << "half a millimetre into the post";
}

TEST(FreeMotion, BlockOnThePlateFreeUntilItsCentreOfMassReachesTheEdge) {
  Assembly a = ctest::loadBundled("block-on-plate.vaw.json");
  const PartId block = *a.findPart("block");
  for (const double tilt : {0.0, 30.0}) {
    a.parts[*a.base].pose = tilted(tilt);
    const CollisionWorld w(a);
    const Support s = w.support(a.constraints[0]);
    ASSERT_TRUE(s.problem.empty()) << s.problem;
    const Eigen::Isometry3d start = tilted(tilt) * *a.parts[block].finalPose;
    const FreeMotion f = w.freeMotion(s, start);
    // The plate's top (300 x 200 mm, convex) and the block's bottom face (convex): free while the centre of
    // mass, at (40, 20) mm, stays on the plate: 80 mm from its nearest edge (y = 100 mm).
    EXPECT_NEAR(f.radius, 0.08, 1e-6) << tilt;
    EXPECT_EQ(f.atMax, FreeMotion::Bound::Touch);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const Eigen::Vector3d e1 = tilted(tilt).linear() * Eigen::Vector3d::UnitX(), e2 = tilted(tilt).linear() * Eigen::Vector3d::UnitY();
    for (int k = 0; k < 40; ++k) {
      const double angle = 2.0 * std::numbers::pi * u(rng), r = (k < 8 ? 0.999 : u(rng)) * f.radius;
      Eigen::Isometry3d p = start;
      p.pretranslate(r * (std::cos(angle) * e1 + std::sin(angle) * e2));
      EXPECT_TRUE(w.touching(s, p).touching) << tilt << " " << angle << " " << r;
      EXPECT_FALSE(w.blocked(s, p).blocked) << tilt << " " << angle << " " << r;
    }
    // Towards the nearest edge (+y), two tolerances and a half beyond the radius, touch is lost.
    Eigen::Isometry3d beyond = start;
    beyond.pretranslate((f.radius + 2.5 * kMotionTol) * e2);
    EXPECT_FALSE(w.touching(s, beyond).touching);
  }
}

TEST(FreeMotion, AWallOnTheBaseAndAnotherPartBoundIt) {
  // A 60 x 40 x 30 mm block on a 300 x 200 mm plate whose wall stands at x = 100 mm; a second part, a box
  // standing on the plate at y = -60 mm. The free radius ends at the nearer of the two, half a tolerance in.
  ctest::SceneBuilder b;
  TriMesh base = primitives::box({0.3, 0.2, 0.04});
  base.append(primitives::box({0.01, 0.2, 0.05}), at(0.105, 0, 0.045));
  b.part("base", std::move(base), at(0, 0, 0));
  b.part("block", primitives::box({0.06, 0.04, 0.03}), at(0.04, 0.0, 0.035), 2700.0);
  b.part("crate", primitives::box({0.04, 0.04, 0.04}), at(0.0, -0.06, 0.04));
  b.base(0);
  b.mate(1, {0, 0, -0.015}, {0, 0, -1}, {0, 0, 0.02}, {0, 0, 1});
  const CollisionWorld w(b.a);
  const Support s = w.support(b.a.constraints[0]);
  ASSERT_TRUE(s.problem.empty()) << s.problem;
  const FreeMotion f = w.freeMotion(s, at(0.04, 0.0, 0.035));
  // The block's box spans y -20..20 mm, the crate's -80..-40 mm: 20 mm apart; the wall is 30 mm away.
  EXPECT_NEAR(f.radius, 0.02 + 0.5 * kMotionTol, 1e-9);
  EXPECT_EQ(f.atMax, FreeMotion::Bound::Obstacle);
  EXPECT_FALSE(w.blocked(s, at(0.04, -0.02 + 1e-6, 0.035)).blocked);
  EXPECT_TRUE(w.blocked(s, at(0.04, -0.02 - 2e-5, 0.035)).blocked) << "into the crate";
  // Moved next to the wall: bound by it.
  const FreeMotion nearWall = w.freeMotion(s, at(0.065, 0.05, 0.035));
  EXPECT_NEAR(nearWall.radius, 0.005 + 0.5 * kMotionTol, 1e-9);
}
