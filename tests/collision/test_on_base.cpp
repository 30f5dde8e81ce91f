// The two checks of a part on its base (touching, blocked) and where along the motion they change.
// Tolerances: Tolerances::distance = 10 um; the time-of-impact search brackets an event to 10 um of motion.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "collision_test_support.hpp"
#include "vaw/collision/time_of_impact.hpp"
#include "vaw/primitives.hpp"

using namespace vaw;
using namespace vaw::collision;
using ctest::at;

namespace {

constexpr double kTol = 1e-5;  // the world's distance tolerance and the search tolerance

struct BlockOnPlate {
  Assembly a = ctest::loadBundled("block-on-plate.vaw.json");
  PartId block = *a.findPart("block");
  Eigen::Isometry3d start;
  CollisionWorld world;
  Support support;
  BlockOnPlate() : start(*a.parts[*a.findPart("block")].finalPose), world(place(a, start)), support(world.support(a.constraints[0])) {}
  static const Assembly& place(Assembly& a, const Eigen::Isometry3d& p) {
    a.parts[*a.findPart("block")].pose = p;
    return a;
  }
};

}  // namespace

// Bundled block-on-plate: the block (60 x 40 x 30 mm, turned 15 degrees, CM at x = 40 mm) slides along +x
// towards the plate's edge at x = 150 mm. Its leading corner passes the edge after 75.8 mm; the CM after
// 110 mm, and only then is touch lost.
TEST(OnBase, BlockSlidingOffThePlateLosesTouchWhenItsCentreOfMassPassesTheEdge) {
  BlockOnPlate t;
  ASSERT_TRUE(t.support.problem.empty()) << t.support.problem;
  const TouchResult at0 = t.world.touching(t.support);
  ASSERT_TRUE(at0.touching) << at0.reason;
  EXPECT_NEAR(at0.supportArea, 0.06 * 0.04, 1e-12) << "the whole bottom face rests on the plate";
  EXPECT_FALSE(t.world.blocked(t.support).blocked) << "no snag on the face it rests on";

  const double comX = (t.start * t.world.centreOfMass(t.block)).x();
  const double expected = 0.150 - comX;  // travel at which the CM is over the edge
  EXPECT_NEAR(expected, 0.110, 1e-6);
  const Motion m = translation(t.start, Eigen::Vector3d::UnitX(), 0.2);
  const MotionEvent ev = firstEventOnBase(t.world, t.support, m);
  ASSERT_EQ(ev.kind, EventKind::LostTouch) << "blocked by " << (ev.contacts.empty() ? -1 : ev.contacts[0].triangleB);
  RecordProperty("lost_touch_error", ctest::um(ev.sEvent - expected));
  EXPECT_NEAR(ev.sEvent, expected, 2 * kTol);
  EXPECT_LE(ev.sEvent - ev.s, kTol);
  EXPECT_FALSE(ev.touch.touching);

  // Not before: still touching (and never blocked) everywhere up to 0.1 mm before the CM reaches the
  // edge, including after the leading corner has left the plate at ~75.8 mm.
  for (double s = 0.0; s <= expected - 1e-4; s += 0.005) {
    const TouchResult tr = t.world.touching(t.support, m.pose(s));
    EXPECT_TRUE(tr.touching) << "at " << s << ": " << tr.reason;
    EXPECT_NEAR(tr.margin, std::min(0.020, expected - s), 1e-9) << "distance to the nearest edge of the support polygon";
    EXPECT_FALSE(t.world.blocked(t.support, m.pose(s)).blocked) << "snagged at " << s;
  }
  const TouchResult before = t.world.touching(t.support, m.pose(expected - 1e-4));
  EXPECT_TRUE(before.touching);
  EXPECT_NEAR(before.margin, 1e-4, 1e-9) << "the margin is the CM's distance to the support polygon's edge";
  EXPECT_LT(before.supportArea, 0.06 * 0.04) << "part of the face hangs over the edge";
}

TEST(OnBase, BlockSlidingDiagonallyLosesTouchAtTheFirstEdgeTheCentreOfMassCrosses) {
  BlockOnPlate t;
  // 2-D slide at 1 m/s along 30 degrees: the CM (40, 20) mm reaches x = 150 mm after 127.0 mm of travel,
  // before y = 100 mm (160 mm).
  const double ang = std::numbers::pi / 6.0;
  const Eigen::Vector2d v(std::cos(ang), std::sin(ang));
  const Motion m = planeSlide(t.start, Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), v, Eigen::Vector2d::Zero(), 0.3);
  const double comX = (t.start * t.world.centreOfMass(t.block)).x();
  const double expected = (0.150 - comX) / std::cos(ang);
  const MotionEvent ev = firstEventOnBase(t.world, t.support, m);
  ASSERT_EQ(ev.kind, EventKind::LostTouch);
  EXPECT_NEAR(ev.sEvent, expected, 2 * kTol);
}

namespace {

// A steel plate 300 x 200 x 40 mm (top at z = 20 mm) with a wall (or fin) standing on it as part of the
// same base mesh, and a 60 x 40 x 30 mm block resting on the plate. The wall's face towards the block is at
// x = wallX.
struct BlockAndWall {
  static constexpr double kTop = 0.02;
  Constraint sup;
  CollisionWorld world;
  Support support;
  PartId block = 1;
  BlockAndWall(double wallX, double wallThickness, double blockX, int plateGrid = 1)
      : world(make(wallX, wallThickness, blockX, plateGrid, sup)), support(world.support(sup)) {}
  static Assembly make(double wallX, double thick, double blockX, int grid, Constraint& c) {
    ctest::SceneBuilder b;
    TriMesh base = grid > 1 ? primitives::gridBox({0.3, 0.2, 0.04}, grid) : primitives::box({0.3, 0.2, 0.04});
    base.append(primitives::box({thick, 0.2, 0.05}), at(wallX + thick / 2, 0, kTop + 0.025));
    b.part("base", std::move(base), at(0, 0, 0));
    b.part("block", primitives::box({0.06, 0.04, 0.03}), at(blockX, 0.0, kTop + 0.015), 2700.0);
    b.base(0);
    c = b.mate(1, {0, 0, -0.015}, {0, 0, -1}, {0, 0, kTop}, {0, 0, 1});
    return b.a;
  }
};

struct SlideRun {
  bool blocked = false;
  double x = 0.0;  // block centre where it stopped
  int steps = 0;
  std::optional<ObjectId> by;
};

// Steps a 1-D slide at `rate` Hz with the closed-form motion of each step and stops at the first event.
SlideRun slide(BlockAndWall& t, double v0, double a, double rate, double maxTime) {
  SlideRun run;
  const double h = 1.0 / rate;
  Eigen::Isometry3d pose = t.world.pose(ObjectId::part(t.block));
  double v = v0;
  for (double time = 0.0; time < maxTime; time += h) {
    const Motion m = axisSlide(pose, Eigen::Vector3d::UnitX(), v, a, h);
    const MotionEvent ev = firstEventOnBase(t.world, t.support, m);
    ++run.steps;
    if (ev.kind == EventKind::Blocked) {
      pose = m.pose(ev.s);
      t.world.setPose(ObjectId::part(t.block), pose);
      run.blocked = true;
      run.by = ev.other;
      break;
    }
    EXPECT_EQ(ev.kind, EventKind::None);
    pose = m.pose(h);
    v += a * h;
    t.world.setPose(ObjectId::part(t.block), pose);
  }
  run.x = pose.translation().x();
  return run;
}

}  // namespace

TEST(OnBase, BlockSlidingIntoAWallIsBlockedAtContact) {
  const double wallX = 0.10, blockX0 = -0.05;
  const double contactX = wallX - 0.03;  // block centre when its front face meets the wall
  for (double rate : {30.0, 60.0, 90.0}) {
    for (double a : {0.0, 2.0}) {
      BlockAndWall t(wallX, 0.02, blockX0);
      ASSERT_TRUE(t.support.problem.empty());
      const SlideRun run = slide(t, 0.5, a, rate, 1.0);
      ASSERT_TRUE(run.blocked) << rate << " Hz";
      ASSERT_TRUE(run.by && *run.by == ObjectId::part(0));
      const double err = run.x - contactX;
      RecordProperty("wall_error_" + std::to_string(static_cast<int>(rate)) + "Hz_a" + std::to_string(static_cast<int>(a)), ctest::um(err));
      EXPECT_LE(std::abs(err), 1e-4) << rate << " Hz, a = " << a;
      EXPECT_LE(err, 2 * kTol) << "at most the touching allowance past the wall";
      EXPECT_GE(err, -2 * kTol) << "stopped at contact, not a step early";
      // Where it stopped it touches the plate and is not blocked; a hair further it is.
      EXPECT_TRUE(t.world.touching(t.support).touching);
      EXPECT_FALSE(t.world.blocked(t.support).blocked);
      Eigen::Isometry3d further = t.world.pose(ObjectId::part(t.block));
      further.pretranslate(Eigen::Vector3d(3 * kTol, 0, 0));
      EXPECT_TRUE(t.world.blocked(t.support, further).blocked);
    }
  }
}

TEST(OnBase, FastSlideDoesNotTunnelThroughAThinFin) {
  // 5 m/s at 30 Hz is 167 mm per step: the 60 mm block would jump clean over a 2 mm fin.
  const double finX = 0.10, contactX = finX - 0.03;
  BlockAndWall t(finX, 0.002, -0.03, 8);
  Eigen::Isometry3d end = t.world.pose(ObjectId::part(t.block));
  end.pretranslate(Eigen::Vector3d(5.0 / 30.0, 0, 0));
  ASSERT_FALSE(t.world.blocked(t.support, end).blocked) << "the end of the step alone sees nothing";
  const SlideRun run = slide(t, 5.0, 0.0, 30.0, 0.2);
  ASSERT_TRUE(run.blocked);
  EXPECT_EQ(run.steps, 1);
  EXPECT_LE(std::abs(run.x - contactX), 1e-4);
  RecordProperty("fin_error", ctest::um(run.x - contactX));
}

namespace {

struct SleeveOnShaft {
  Assembly a = ctest::loadBundled("sleeve-on-shaft.vaw.json");
  PartId sleeve = *a.findPart("sleeve");
  CollisionWorld world;
  Support support;
  explicit SleeveOnShaft(const Eigen::Isometry3d& pose) : world(place(a, pose)), support(world.support(a.constraints[0])) {}
  static const Assembly& place(Assembly& a, const Eigen::Isometry3d& p) {
    a.parts[*a.findPart("sleeve")].pose = p;
    return a;
  }
};

}  // namespace

// Bundled sleeve-on-shaft: bore r 15 mm on a 15 mm shaft with coincident vertices. The shaft rises from the
// block's top face (z = 40 mm, the shoulder) to its chamfer at z = 159 mm.
TEST(OnBase, SleeveOnItsShaftIsNotBlockedByTheCoaxialSurfaces) {
  for (double turn : {0.0, std::numbers::pi / 64.0, 0.3}) {  // aligned, half a segment off, arbitrary
    Eigen::Isometry3d p = at(0, 0, 0.100);
    p.rotate(Eigen::AngleAxisd(turn, Eigen::Vector3d::UnitZ()));
    SleeveOnShaft t(p);
    ASSERT_TRUE(t.support.problem.empty()) << t.support.problem;
    ASSERT_EQ(t.support.kind, Support::Kind::Axis);
    const TouchResult tr = t.world.touching(t.support);
    EXPECT_TRUE(tr.touching);
    EXPECT_NEAR(tr.margin, 0.040, 1e-9) << "the whole 40 mm bore is on the shaft";
    EXPECT_FALSE(t.world.blocked(t.support).blocked) << "turn " << turn;
    // The plain query does see the bore on the shaft.
    EXPECT_FALSE(t.world.query(ObjectId::part(t.sleeve), ObjectId::part(*t.a.base)).contacts.empty());
    // Turning about the axis never blocks either.
    for (int k = 0; k < 36; ++k) {
      Eigen::Isometry3d q = p;
      q.rotate(Eigen::AngleAxisd(k * std::numbers::pi / 18.0 + 0.013, Eigen::Vector3d::UnitZ()));
      EXPECT_FALSE(t.world.blocked(t.support, q).blocked) << "turn " << turn << " + " << k * 10 << " deg";
    }
  }
}

TEST(OnBase, SleeveSlidingDownIsBlockedByTheShoulder) {
  for (double turn : {0.0, std::numbers::pi / 64.0}) {
    Eigen::Isometry3d p = at(0, 0, 0.100);
    p.rotate(Eigen::AngleAxisd(turn, Eigen::Vector3d::UnitZ()));
    SleeveOnShaft t(p);
    const Motion m = translation(p, -Eigen::Vector3d::UnitZ(), 0.08);
    const MotionEvent ev = firstEventOnBase(t.world, t.support, m);
    ASSERT_EQ(ev.kind, EventKind::Blocked) << "turn " << turn;
    ASSERT_TRUE(ev.other && *ev.other == ObjectId::part(*t.a.base));
    const double expected = 0.060;  // the sleeve's bottom face reaches the block's top face
    RecordProperty("shoulder_error_turn" + std::to_string(turn), ctest::um(ev.s - expected));
    EXPECT_LE(std::abs(ev.s - expected), 1e-4);
    EXPECT_LE(std::abs(ev.s - expected), 2 * kTol) << "turn " << turn;
    EXPECT_TRUE(ev.touch.touching) << "still on the shaft where it stops";
  }
}

TEST(OnBase, SleeveSlidingOffTheFreeEndLosesTouchThere) {
  const Eigen::Isometry3d p = at(0, 0, 0.100);
  SleeveOnShaft t(p);
  const Motion m = translation(p, Eigen::Vector3d::UnitZ(), 0.08);
  const MotionEvent ev = firstEventOnBase(t.world, t.support, m);
  ASSERT_EQ(ev.kind, EventKind::LostTouch) << "nothing blocks it on the way up";
  const double expected = 0.059;  // the bore's lower end passes the end of the shaft's cylinder (159 mm)
  RecordProperty("free_end_error", ctest::um(ev.sEvent - expected));
  EXPECT_NEAR(ev.sEvent, expected, 2 * kTol);
  EXPECT_LE(ev.sEvent - ev.s, kTol);
  // Just before, 0.1 mm of bore is still on the shaft.
  const TouchResult before = t.world.touching(t.support, m.pose(expected - 1e-4));
  EXPECT_TRUE(before.touching);
  EXPECT_NEAR(before.margin, 1e-4, 1e-9);
}

TEST(OnBase, AConstraintThatMatchesNoFaceIsReportedNotGuessed) {
  BlockOnPlate t;
  Constraint c = t.a.constraints[0];
  c.partPlane.point.z() = -0.010;  // 5 mm inside the block: no face there
  const Support s = t.world.support(c);
  EXPECT_FALSE(s.problem.empty());
  const TouchResult tr = t.world.touching(s);
  EXPECT_FALSE(tr.touching);
  EXPECT_EQ(tr.reason, s.problem);
}

TEST(OnBase, LiftedOrTiltedPartIsNotTouching) {
  BlockOnPlate t;
  Eigen::Isometry3d up = t.start;
  up.pretranslate(Eigen::Vector3d(0, 0, 2 * kTol));
  const TouchResult lifted = t.world.touching(t.support, up);
  EXPECT_FALSE(lifted.touching);
  EXPECT_NEAR(lifted.separation, 2 * kTol, 1e-12);
  Eigen::Isometry3d nearly = t.start;
  nearly.pretranslate(Eigen::Vector3d(0, 0, 0.5 * kTol));
  EXPECT_TRUE(t.world.touching(t.support, nearly).touching) << "a gap within the tolerance still touches";
  Eigen::Isometry3d tilted = t.start;
  tilted.rotate(Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitX()));
  EXPECT_FALSE(t.world.touching(t.support, tilted).touching);
}

TEST(OnBase, SkippingTheSupportSurfaceNeverChangesTheAnswer) {
  // The blocked check skips the base's geometry under a resting face / inside a fitting bore (Support's
  // cache). Without the cache it tests everything: both must agree along the motions above.
  auto agree = [](const CollisionWorld& w, const Support& s, const Motion& m, int samples) {
    Support plain = s;
    plain.cache.reset();
    int blocked = 0;
    for (int k = 0; k <= samples; ++k) {
      const Eigen::Isometry3d p = m.pose(m.s0 + (m.s1 - m.s0) * k / samples);
      const BlockResult a = w.blocked(s, p), b = w.blocked(plain, p);
      EXPECT_EQ(a.blocked, b.blocked) << "sample " << k;
      EXPECT_LE(a.boundingVolumeTests, b.boundingVolumeTests);
      blocked += a.blocked ? 1 : 0;
    }
    return blocked;
  };
  {
    BlockAndWall t(0.10, 0.02, -0.05, 4);
    ASSERT_TRUE(t.support.cache);
    const Motion m = translation(t.world.pose(ObjectId::part(t.block)), Eigen::Vector3d::UnitX(), 0.15);
    EXPECT_GT(agree(t.world, t.support, m, 60), 0) << "the path runs into the wall";
  }
  {
    SleeveOnShaft t(at(0, 0, 0.100));
    ASSERT_TRUE(t.support.cache);
    EXPECT_GT(agree(t.world, t.support, translation(at(0, 0, 0.100), -Eigen::Vector3d::UnitZ(), 0.08), 40), 0);
    Eigen::Isometry3d turned = at(0, 0, 0.08);
    turned.rotate(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
    EXPECT_EQ(agree(t.world, t.support, translation(turned, Eigen::Vector3d::UnitZ(), 0.05), 25), 0);
  }
}

// Bundled gear-on-shaft: the gear's bore (r 10 mm, 64 segments, off the gear's centre) on a horizontal
// shaft along x (from the post's face at x = -120 mm to its free end at x = 130 mm); the gear's faces are
// 3.065 mm either side of its frame. It turns freely, is stopped by the post, and falls off the free end.
TEST(OnBase, GearOnItsShaftTurnsFreelyIsStoppedByThePostAndFallsOffTheEnd) {
  Assembly a = ctest::loadBundled("gear-on-shaft.vaw.json");
  const PartId gear = *a.findPart("gear");
  const Eigen::Isometry3d start = *a.parts[gear].finalPose;
  a.parts[gear].pose = start;
  CollisionWorld w(a);
  const Support s = w.support(a.constraints[0]);
  ASSERT_TRUE(s.problem.empty()) << s.problem;
  ASSERT_TRUE(w.touching(s).touching);
  ASSERT_FALSE(w.blocked(s).blocked);
  // A full turn about the shaft, as the hinge model moves it.
  const auto hinge = dyn::Hinge::make(a.constraints[0].baseAxis.point, a.constraints[0].baseAxis.direction,
                                      w.pose(ObjectId::part(*a.base)).inverse() * start, a.parts[gear].mass.mass,
                                      a.parts[gear].mass.centerOfMass, a.parts[gear].mass.inertiaCm, 0.0);
  ASSERT_TRUE(hinge);
  const double radius = w.maxRadius(ObjectId::part(gear), a.constraints[0].partAxis);
  const Motion turn = hingeRotation(*hinge, w.pose(ObjectId::part(*a.base)), 0.0, 2.0 * std::numbers::pi, radius);
  const MotionEvent spin = firstEventOnBase(w, s, turn);
  EXPECT_EQ(spin.kind, EventKind::None) << "turning is never blocked by its own bore";
  EXPECT_GT(spin.evaluations, 100) << "sampled at least every mm of the teeth's travel";
  // The same without the support's skipping (every pair tested): the bore's own pairs and its end faces
  // on the shaft are left out by SKIP_COAXIAL alone.
  Support plain = s;
  plain.cache.reset();
  for (int k = 0; k < 72; ++k) {
    const BlockResult b = w.blocked(plain, turn.pose(k * std::numbers::pi / 36.0 + 0.01));
    EXPECT_FALSE(b.blocked) << k * 5 << " deg: " << (b.contacts.empty() ? 0.0 : b.contacts[0].penetration);
  }
  // Along the shaft towards the post, and off the free end.
  const double face = 0.0030650;
  const MotionEvent left = firstEventOnBase(w, s, translation(start, -Eigen::Vector3d::UnitX(), 0.25));
  ASSERT_EQ(left.kind, EventKind::Blocked);
  EXPECT_NEAR(left.s, 0.060 - (-0.120 + face), 1e-4);
  RecordProperty("gear_post_error", ctest::um(left.s - (0.060 - (-0.120 + face))));
  const MotionEvent right = firstEventOnBase(w, s, translation(start, Eigen::Vector3d::UnitX(), 0.25));
  ASSERT_EQ(right.kind, EventKind::LostTouch);
  EXPECT_NEAR(right.sEvent, 0.130 - 0.060 + face, 2 * kTol);
  RecordProperty("gear_free_end_error", ctest::um(right.sEvent - (0.130 - 0.060 + face)));
}
