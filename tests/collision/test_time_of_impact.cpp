// Free flight stops at first contact: conservative advancement on the distance, any step rate, no
// tunnelling. The part is left with a gap in (tolerance / 2, tolerance] = (5, 10] um.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "collision_test_support.hpp"
#include "vaw/collision/time_of_impact.hpp"
#include "vaw/dynamics/gravity.hpp"
#include "vaw/primitives.hpp"

using namespace vaw;
using namespace vaw::collision;
using ctest::at;

namespace {

constexpr double kImpactTol = 1e-5;

double lowestZ(const CollisionWorld& w, ObjectId id, const Eigen::Isometry3d& pose) {
  double z = std::numeric_limits<double>::infinity();
  for (const auto& v : w.collisionMesh(id)->vertices) z = std::min(z, (pose * v).z());
  return z;
}

struct Drop {
  bool hit = false;
  double time = 0.0;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  std::optional<ObjectId> other;
  int evaluations = 0;
};

// Free flight stepped at `rate` Hz; each step's closed-form arc is searched for the first contact.
Drop fly(CollisionWorld& w, PartId part, const dyn::Release& r, const Eigen::Vector3d& g, double rate, double maxTime) {
  Drop d;
  const ObjectId id = ObjectId::part(part);
  const Eigen::Vector3d com = w.centreOfMass(part);
  const double radius = w.maxRadius(id, com);
  const double h = 1.0 / rate;
  for (double t = r.t0; t < r.t0 + maxTime; t += h) {
    const Motion m = ballistic(r, g, com, t, t + h, radius);
    const MotionEvent ev = timeOfImpact(w, id, m);
    d.evaluations += ev.evaluations;
    d.pose = m.pose(ev.s);
    w.setPose(id, d.pose);
    if (ev.kind == EventKind::Contact) {
      d.hit = true;
      d.time = ev.s;
      d.other = ev.other;
      EXPECT_LE(ev.distance, kImpactTol);
      break;
    }
  }
  return d;
}

}  // namespace

// The bundled block dropped from 1 m (its bottom face 1 m above the table's top at z = 0), well away from
// the plate, under the free-flight gravity scale and under full gravity, at 30 to 90 Hz.
TEST(TimeOfImpact, PartDroppedOntoTheTableStopsOnItsSurface) {
  for (bool primitiveTable : {true, false}) {
    for (double scale : {0.25, 1.0}) {
      for (double rate : {30.0, 60.0, 90.0}) {
        Assembly a = ctest::loadBundled("block-on-plate.vaw.json");
        const PartId block = *a.findPart("block");
        a.parts[block].pose = at(0.5, 0.2, 1.0 + 0.015);
        WorldOptions opt;
        opt.environmentPrimitives = primitiveTable;
        CollisionWorld w(a, opt);
        ASSERT_EQ(w.info(ObjectId::environment(0)).proxy, primitiveTable ? ProxyKind::Box : ProxyKind::Mesh);
        dyn::Release r;
        r.position = a.parts[block].pose * w.centreOfMass(block);
        const Eigen::Vector3d g = scale * dyn::worldGravity();
        const Drop d = fly(w, block, r, g, rate, 3.0);
        ASSERT_TRUE(d.hit);
        ASSERT_TRUE(d.other && *d.other == ObjectId::environment(0)) << "hit the table";
        const double gap = lowestZ(w, ObjectId::part(block), d.pose);
        RecordProperty("drop_gap_" + std::string(primitiveTable ? "box_" : "mesh_") + std::to_string(static_cast<int>(rate)) + "Hz_g" + std::to_string(scale), ctest::um(gap));
        EXPECT_GE(gap, 0.0) << "never below the table's surface";
        EXPECT_LE(gap, 1e-4) << "within 0.1 mm of it";
        EXPECT_LE(gap, kImpactTol);
        EXPECT_NEAR(d.time, std::sqrt(2.0 * 1.0 / (scale * kStandardGravity)), 1e-4) << "the fall time of 1 m";
      }
    }
  }
}

TEST(TimeOfImpact, TumblingPartStopsAtItsLowestCorner) {
  Assembly a = ctest::loadBundled("block-on-plate.vaw.json");
  const PartId block = *a.findPart("block");
  a.parts[block].pose = at(0.5, 0.2, 1.0);
  CollisionWorld w(a);
  dyn::Release r;
  r.position = a.parts[block].pose * w.centreOfMass(block);
  r.omega = Eigen::Vector3d(2.0, 3.0, 1.0);
  r.velocity = Eigen::Vector3d(0.1, 0.1, 0.5);  // lands on the table, clear of the plate
  const Drop d = fly(w, block, r, 0.25 * dyn::worldGravity(), 30.0, 4.0);
  ASSERT_TRUE(d.hit);
  const double gap = lowestZ(w, ObjectId::part(block), d.pose);
  EXPECT_GE(gap, 0.0);
  EXPECT_LE(gap, kImpactTol);
}

TEST(TimeOfImpact, FastPartDoesNotTunnelThroughAThinPlate) {
  // A 10 mm cube at 5 m/s towards a 2 mm plate (an environment fixture), no gravity, 30 Hz: one step is
  // 167 mm, enough to jump over the plate entirely.
  ctest::SceneBuilder b;
  b.part("cube", primitives::box({0.01, 0.01, 0.01}), at(0, 0, 0.5));
  b.environment("plate", primitives::box({0.002, 0.2, 0.2}), at(0.1, 0, 0.5), "primitive box");
  CollisionWorld w(b.a);
  const ObjectId cube = ObjectId::part(0);
  dyn::Release r;
  r.position = Eigen::Vector3d(0, 0, 0.5);
  r.velocity = Eigen::Vector3d(5.0, 0, 0);
  const Motion m = ballistic(r, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0.0, 1.0 / 30.0, w.maxRadius(cube, Eigen::Vector3d::Zero()));
  ASSERT_FALSE(w.colliding(cube, m.pose(m.s1)).blocked) << "the end of the step alone sees nothing";
  const MotionEvent ev = timeOfImpact(w, cube, m);
  ASSERT_EQ(ev.kind, EventKind::Contact);
  const double front = m.pose(ev.s).translation().x() + 0.005;
  const double gap = 0.099 - front;
  RecordProperty("thin_plate_gap", ctest::um(gap));
  EXPECT_GT(gap, 0.0);
  EXPECT_LE(gap, kImpactTol);
  EXPECT_LT(ev.evaluations, 50) << "advancement converges in a few distance queries";
  RecordProperty("thin_plate_distance_queries", ev.evaluations);
}

TEST(TimeOfImpact, GrazingPassDoesNotStop) {
  // The cube passes 1 mm beside the plate's edge: no contact, the whole step is taken.
  ctest::SceneBuilder b;
  b.part("cube", primitives::box({0.01, 0.01, 0.01}), at(0, 0.106, 0.5));
  b.environment("plate", primitives::box({0.002, 0.2, 0.2}), at(0.1, 0, 0.5), "primitive box");
  CollisionWorld w(b.a);
  dyn::Release r;
  r.position = Eigen::Vector3d(0, 0.106, 0.5);
  r.velocity = Eigen::Vector3d(5.0, 0, 0);
  const Motion m = ballistic(r, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0.0, 1.0 / 30.0, 0.01);
  const MotionEvent ev = timeOfImpact(w, ObjectId::part(0), m);
  EXPECT_EQ(ev.kind, EventKind::None);
  EXPECT_DOUBLE_EQ(ev.s, m.s1);
}

TEST(TimeOfImpact, HingeRotationStopsAtAStop) {
  // A lever (100 x 10 x 10 mm) turning about the z axis through its end, on a base with a stop post
  // 50 mm from the axis on the +y side: blocked when the lever's side face reaches the post.
  ctest::SceneBuilder b;
  TriMesh base = primitives::cylinder(0.005, 0.04, 64);
  base.append(primitives::box({0.01, 0.01, 0.04}), at(0.05, 0.02 + 0.005, 0));
  b.part("base", std::move(base), at(0, 0, 0));
  TriMesh lever = primitives::box({0.094, 0.01, 0.01});  // x from 6 mm (clear of the shaft) to 100 mm
  lever.transform(Eigen::Isometry3d(Eigen::Translation3d(0.053, 0, 0)));
  lever.append(primitives::tube(0.008, 0.005, 0.01, 64));
  const PartId leverId = b.part("lever", std::move(lever), at(0, 0, 0));
  b.base(0);
  const Constraint c = b.insert(leverId, {0, 0, 0}, {0, 0, 1}, {0, 0, 0}, {0, 0, 1});
  CollisionWorld w(b.a);
  const Support s = w.support(c);
  ASSERT_TRUE(s.problem.empty()) << s.problem;
  auto hinge = dyn::Hinge::make({0, 0, 0}, {0, 0, 1}, Eigen::Isometry3d::Identity(), 0.1, {0.05, 0, 0},
                                Eigen::Matrix3d::Identity() * 1e-4, 0.0);
  ASSERT_TRUE(hinge);
  const double radius = w.maxRadius(ObjectId::part(leverId), Axis{{0, 0, 0}, {0, 0, 1}});
  const Motion m = hingeRotation(*hinge, Eigen::Isometry3d::Identity(), 0.0, 1.0, radius);
  const MotionEvent ev = firstEventOnBase(w, s, m);
  ASSERT_EQ(ev.kind, EventKind::Blocked);
  // The lever's +y face (5 mm from the axis) reaches a corner P of the post (x in [45, 55] mm, y = 20 mm)
  // at the angle a with |P| sin(atan2(P) - a) = 5 mm; the far corner comes first.
  double expected = 1e9, arm = 0.0;
  for (double x : {0.045, 0.055}) {
    const double rp = std::hypot(x, 0.02), ap = std::atan2(0.02, x) - std::asin(0.005 / rp);
    if (ap < expected) {
      expected = ap;
      arm = rp;
    }
  }
  const double err = (ev.s - expected) * arm;  // along the arc at the contact
  RecordProperty("hinge_error", ctest::um(err));
  EXPECT_LE(std::abs(err), 3 * kImpactTol);
  EXPECT_LE(std::abs(err), 1e-4);
}

// ---- one pair's way (assembly evaluation) ----

TEST(FirstBlockBy, ACubeMovingAtAWallStopsAtItsFaceAfterFewChecks) {
  // A 10 mm cube 50 mm from a 10 mm wall (face to face), moved 100 mm toward it.
  ctest::SceneBuilder b;
  const PartId cube = b.part("cube", primitives::box({0.01, 0.01, 0.01}), at(0, 0, 0.5));
  const PartId wall = b.part("wall", primitives::box({0.01, 0.1, 0.1}), at(0.06, 0, 0.5));
  b.base(wall);
  const CollisionWorld w(b.a);
  const MotionEvent ev = firstBlockBy(w, ObjectId::part(cube), ObjectId::part(wall),
                                      translation(at(0, 0, 0.5), Eigen::Vector3d::UnitX(), 0.1), FilterMode::NoCare);
  ASSERT_EQ(ev.kind, EventKind::Blocked);
  EXPECT_FALSE(ev.initiallyBlocked);
  // Faces within the distance tolerance only touch, so the last free pose is up to that far past contact.
  EXPECT_NEAR(ev.s, 0.05, 1e-5 + ToiOptions{}.tolerance);
  EXPECT_LE((ev.sEvent - ev.s), ToiOptions{}.tolerance);
  EXPECT_LT(ev.evaluations, 40) << "conservative advancement across the gap, a few samples at the face";
  // Moved away from it, nothing.
  const MotionEvent away = firstBlockBy(w, ObjectId::part(cube), ObjectId::part(wall),
                                        translation(at(0, 0, 0.5), -Eigen::Vector3d::UnitX(), 0.1), FilterMode::NoCare);
  EXPECT_EQ(away.kind, EventKind::None);
}

TEST(FirstBlockBy, APegSlidesOutOfItsBoreButNotThroughItsBottom) {
  // A peg (r 5 mm) in a tube's bore (r 5 mm, no clearance), the tube standing on a plate.
  ctest::SceneBuilder b;
  const PartId plate = b.part("plate", primitives::box({0.08, 0.08, 0.01}), at(0, 0, -0.005));
  const PartId tube = b.part("tube", primitives::tube(0.01, 0.005, 0.02, 48), at(0, 0, 0.01));
  const PartId peg = b.part("peg", primitives::cylinder(0.005, 0.03, 48), at(0, 0, 0.015));
  b.base(plate);
  const CollisionWorld w(b.a);
  // Up along the axis: the coaxial pair is skipped, the peg leaves the bore.
  const Motion up = translation(at(0, 0, 0.015), Eigen::Vector3d::UnitZ(), 0.05);
  EXPECT_EQ(firstBlockBy(w, ObjectId::part(peg), ObjectId::part(tube), up, FilterMode::SkipCoaxial).kind, EventKind::None);
  // Down: its end rests on the plate, which blocks it at once.
  const Motion down = translation(at(0, 0, 0.015), -Eigen::Vector3d::UnitZ(), 0.05);
  const MotionEvent onPlate = firstBlockBy(w, ObjectId::part(peg), ObjectId::part(plate), down, FilterMode::SkipCoaxial);
  ASSERT_EQ(onPlate.kind, EventKind::Blocked);
  // Blocked once it sinks in beyond the 10 um tolerance, located within one tolerance of that.
  EXPECT_LE(onPlate.sEvent, 2e-5 + 1e-12);
  EXPECT_LE(onPlate.evaluations, 6) << "a block at the start is bracketed by one short check, not a whole step's bisection";
  // Sideways, the bore's wall blocks it at once.
  const Motion side = translation(at(0, 0, 0.015), Eigen::Vector3d::UnitX(), 0.05);
  const MotionEvent wall = firstBlockBy(w, ObjectId::part(peg), ObjectId::part(tube), side, FilterMode::SkipCoaxial);
  ASSERT_EQ(wall.kind, EventKind::Blocked);
  EXPECT_LT(wall.sEvent, 1e-3);
}

TEST(FirstBlockBy, OutOfIterationsBeforeTheEndIsUndecidedNotFree) {
  // The cube 2 m before the wall, moved 3 m at it, with room for a single advance.
  ctest::SceneBuilder b;
  const PartId cube = b.part("cube", primitives::box({0.01, 0.01, 0.01}), at(0, 0, 0.5));
  const PartId wall = b.part("wall", primitives::box({0.01, 0.1, 0.1}), at(2.01, 0, 0.5));
  b.base(wall);
  const CollisionWorld w(b.a);
  ToiOptions few;
  few.maxIterations = 1;
  const MotionEvent ev = firstBlockBy(w, ObjectId::part(cube), ObjectId::part(wall),
                                      translation(at(0, 0, 0.5), Eigen::Vector3d::UnitX(), 3.0), FilterMode::NoCare, few);
  EXPECT_EQ(ev.kind, EventKind::None);
  EXPECT_TRUE(ev.undecided);
  EXPECT_NEAR(ev.s, 2.0, 1e-4) << "where it got to: up to the wall, no further";
  // With its iterations it finds the wall.
  EXPECT_EQ(firstBlockBy(w, ObjectId::part(cube), ObjectId::part(wall), translation(at(0, 0, 0.5), Eigen::Vector3d::UnitX(), 3.0),
                         FilterMode::NoCare)
                .kind,
            EventKind::Blocked);
}

TEST(SweepDistance, WhatATranslationPassesAtAClearanceIsLeftOut) {
  // A tube (bore r 4.5 mm, outside r 8 mm, 20 mm long) 20 mm over a plate, round a pin (r 4 mm) standing
  // on the plate: moved down its axis the tube can meet the plate, never the pin.
  ctest::SceneBuilder b;
  const PartId plate = b.part("plate", primitives::box({0.08, 0.08, 0.01}), at(0, 0, -0.005));
  const PartId pin = b.part("pin", primitives::cylinder(0.004, 0.05, 48), at(0, 0, 0.025));
  const PartId tube = b.part("tube", primitives::tube(0.008, 0.0045, 0.02, 48), at(0, 0, 0.03));
  b.base(plate);
  const CollisionWorld w(b.a);
  const Eigen::Isometry3d home = at(0, 0, 0.03);
  const Eigen::Vector3d down = -Eigen::Vector3d::UnitZ();
  EXPECT_LT(w.distance(ObjectId::part(tube), home, ObjectId::part(pin)), 0.0006) << "the pin is half a millimetre from the bore";
  EXPECT_TRUE(std::isinf(w.distanceAlong(ObjectId::part(tube), home, ObjectId::part(pin), FilterMode::SkipCoaxial, down)))
      << "down its axis the tube never meets the pin";
  EXPECT_NEAR(w.distanceAlong(ObjectId::part(tube), home, ObjectId::part(plate), FilterMode::SkipCoaxial, down), 0.02, 1e-9);
  // Sideways the pin is in the way, half a millimetre off (less the facets' sagitta).
  const double side = w.distanceAlong(ObjectId::part(tube), home, ObjectId::part(pin), FilterMode::SkipCoaxial, Eigen::Vector3d::UnitX());
  EXPECT_GT(side, 0.0004);
  EXPECT_LT(side, 0.0006);
  // So the way down its axis costs one distance query, and ends on the plate after 20 mm.
  const MotionEvent pass = firstBlockBy(w, ObjectId::part(tube), ObjectId::part(pin), translation(home, down, 0.03), FilterMode::SkipCoaxial);
  EXPECT_EQ(pass.kind, EventKind::None);
  EXPECT_LE(pass.evaluations, 2);
  const MotionEvent onPlate = firstBlockBy(w, ObjectId::part(tube), ObjectId::part(plate), translation(home, down, 0.03), FilterMode::SkipCoaxial);
  ASSERT_EQ(onPlate.kind, EventKind::Blocked);
  EXPECT_NEAR(onPlate.s, 0.02, 2e-5);
}

TEST(SweepDistance, WhatTheMotionTakesApartIsLeftOutAndACapEndsTheSearch) {
  // A peg (r 5 mm) standing on a disc (r 20 mm, 10 mm thick), and a second peg 20 mm over the disc.
  ctest::SceneBuilder b;
  const PartId disc = b.part("disc", primitives::cylinder(0.02, 0.01, 48), at(0, 0, -0.005));
  const PartId peg = b.part("peg", primitives::cylinder(0.005, 0.02, 32), at(0, 0, 0.01));
  const PartId high = b.part("high peg", primitives::cylinder(0.005, 0.02, 32), at(0.012, 0, 0.03));
  b.base(disc);
  const CollisionWorld w(b.a);
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  EXPECT_LT(w.distance(ObjectId::part(peg), ObjectId::part(disc)), 1e-9) << "the peg stands on the disc";
  EXPECT_TRUE(std::isinf(w.distanceAlong(ObjectId::part(peg), at(0, 0, 0.01), ObjectId::part(disc), FilterMode::SkipCoplanar, up)))
      << "lifted, the peg only leaves the disc";
  EXPECT_LT(w.distanceAlong(ObjectId::part(peg), at(0, 0, 0.01), ObjectId::part(disc), FilterMode::SkipCoplanar, -up), 1e-9)
      << "pushed down it is in contact at once";
  EXPECT_NEAR(w.distanceAlong(ObjectId::part(high), at(0.012, 0, 0.03), ObjectId::part(disc), FilterMode::SkipCoplanar, -up), 0.02, 1e-9);
  EXPECT_DOUBLE_EQ(w.distanceAlong(ObjectId::part(high), at(0.012, 0, 0.03), ObjectId::part(disc), FilterMode::SkipCoplanar, -up, 0.005),
                   0.005)
      << "a caller going no farther than 5 mm learns only that nothing is nearer";
}

TEST(SweepDistance, PartsOnEitherSideOfAFaceTheMotionLiesInOnlyTouch) {
  // A ring (r 5..20 mm, 10 mm high) standing on another drilled alike: their bores' walls and their outer
  // walls meet only along the rims in the plane between them, so slid sideways over the lower one the upper
  // is never blocked, and that costs one distance query instead of a check every millimetre. Pushed into
  // it, it is blocked at once.
  ctest::SceneBuilder b;
  const PartId lower = b.part("lower", primitives::tube(0.02, 0.005, 0.01, 48), at(0, 0, -0.005));
  const PartId upper = b.part("upper", primitives::tube(0.02, 0.005, 0.01, 48), at(0, 0, 0.005));
  b.base(lower);
  const CollisionWorld w(b.a);
  const Eigen::Isometry3d home = at(0, 0, 0.005);
  const Eigen::Vector3d side = Eigen::Vector3d(1, 1, 0).normalized();
  EXPECT_TRUE(std::isinf(w.distanceAlong(ObjectId::part(upper), home, ObjectId::part(lower), FilterMode::SkipCoaxial, side)));
  const MotionEvent slide = firstBlockBy(w, ObjectId::part(upper), ObjectId::part(lower), translation(home, side, 0.1), FilterMode::SkipCoaxial);
  EXPECT_EQ(slide.kind, EventKind::None);
  EXPECT_LE(slide.evaluations, 2);
  const MotionEvent down =
      firstBlockBy(w, ObjectId::part(upper), ObjectId::part(lower), translation(home, -Eigen::Vector3d::UnitZ(), 0.01), FilterMode::SkipCoaxial);
  ASSERT_EQ(down.kind, EventKind::Blocked);
  EXPECT_LT(down.s, 1e-4);
  // A hexagonal post (r 5 mm, 40 mm high) standing on the ring: its bottom is not among its largest faces,
  // but it lies wholly on one side of the ring's top and the ring on the other, so slid across the ring
  // it too only touches, its side faces' lower edges on the ring's face all along.
  ctest::SceneBuilder c;
  const PartId ring = c.part("ring", primitives::tube(0.02, 0.005, 0.01, 48), at(0, 0, -0.005));
  const PartId post = c.part("post", primitives::cylinder(0.005, 0.04, 6), at(0.012, 0, 0.02));
  c.base(ring);
  const CollisionWorld w2(c.a);
  EXPECT_TRUE(std::isinf(w2.distanceAlong(ObjectId::part(post), at(0.012, 0, 0.02), ObjectId::part(ring), FilterMode::SkipCoplanar,
                                          Eigen::Vector3d::UnitY())));
  const MotionEvent across = firstBlockBy(w2, ObjectId::part(post), ObjectId::part(ring), translation(at(0.012, 0, 0.02), Eigen::Vector3d::UnitY(), 0.1),
                                          FilterMode::SkipCoplanar);
  EXPECT_EQ(across.kind, EventKind::None);
  EXPECT_LE(across.evaluations, 2);
  // A millimetre into it, the overlap is found though each wall pair lies across the plane between them.
  QueryOptions q;
  q.dropTouching = true;
  EXPECT_FALSE(w.query(ObjectId::part(upper), at(0.003, 0, 0.004), ObjectId::part(lower), q).contacts.empty());
  EXPECT_TRUE(w.query(ObjectId::part(upper), at(0.003, 0, 0.005), ObjectId::part(lower), q).contacts.empty());
}

TEST(FirstBlockBy, TwoEqualShaftsEndToEndMeetThoughTheirSurfacesNeverCross) {
  // Two rods (r 5 mm, 20 mm long) on one axis, 5 mm apart; a tube whose bore fits the lower rod exactly.
  // Pushed into each other the rods' surfaces cross only at the rims and their coaxial faces coincide, so
  // no surface test sees the block; the shared volume does.
  ctest::SceneBuilder b;
  const PartId upper = b.part("upper", primitives::cylinder(0.005, 0.02, 48), at(0, 0, 0.035));
  const PartId lower = b.part("lower", primitives::cylinder(0.005, 0.02, 48), at(0, 0, 0.01));
  const PartId tube = b.part("tube", primitives::tube(0.01, 0.005, 0.01, 48), at(0.05, 0, 0.005));
  b.base(upper);
  const CollisionWorld w(b.a);
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const Eigen::Isometry3d home = at(0, 0, 0.01);
  EXPECT_NEAR(w.coaxialOverlapAlong(ObjectId::part(lower), home, ObjectId::part(upper), up), 0.005 + 1e-5, 1e-9)
      << "they share volume once the lower one is a tolerance into the upper one";
  EXPECT_TRUE(std::isinf(w.coaxialOverlapAlong(ObjectId::part(lower), home, ObjectId::part(upper), -up)));
  const MotionEvent meet = firstBlockBy(w, ObjectId::part(lower), ObjectId::part(upper), translation(home, up, 0.04), FilterMode::SkipCoaxial);
  ASSERT_EQ(meet.kind, EventKind::Blocked) << "no longer passes through the other rod";
  EXPECT_NEAR(meet.s, 0.005, 2e-5);
  EXPECT_EQ(firstBlockBy(w, ObjectId::part(lower), ObjectId::part(upper), translation(home, -up, 0.04), FilterMode::SkipCoaxial).kind,
            EventKind::None);
  // A shaft in a bore of its own size is the opposite kind: it slides through, nothing shared.
  EXPECT_TRUE(std::isinf(w.coaxialOverlapAlong(ObjectId::part(lower), at(0.05, 0, 0.02), ObjectId::part(tube), -up)));
  // Already 10 mm into the other: blocked where it stands, either way along the axis.
  const MotionEvent inside = firstBlockBy(w, ObjectId::part(lower), ObjectId::part(upper), translation(at(0, 0, 0.025), -up, 0.04),
                                          FilterMode::SkipCoaxial);
  EXPECT_EQ(inside.kind, EventKind::Blocked);
  EXPECT_TRUE(inside.initiallyBlocked);
}

// ---- the order an assembly goes together in, on shapes made in code ----

#include "vaw/evaluation/sequence.hpp"

TEST(PlanSequence, APegUnderABlockGoesInFirstAndAPartWithNoFreeWayIsNamed) {
  ctest::SceneBuilder b;
  const PartId plate = b.part("plate", primitives::box({0.1, 0.1, 0.01}), at(0, 0, -0.005));
  const PartId peg = b.part("peg", primitives::cylinder(0.005, 0.02, 32), at(0, 0, 0.01));
  // A block 3 mm over the peg's top, held up on its own legs: it stands in the peg's way up.
  const PartId block = b.part("block", primitives::box({0.04, 0.04, 0.01}), at(0, 0, 0.028));
  b.base(plate);
  for (const PartId p : {peg, block}) b.a.parts[p].finalPose = b.a.parts[p].pose;
  // The peg stands on the plate and the block comes down from above (home from +z, the default); neither
  // has a partner but the base.
  b.mate(peg, {0, 0, -0.01}, {0, 0, -1}, {0, 0, 0.005}, {0, 0, 1});
  b.mate(block, {0, 0, -0.005}, {0, 0, -1}, {0, 0, 0.018}, {0, 0, 1});
  const eval::SequencePlan plan = eval::planSequence(b.a);
  ASSERT_TRUE(plan.complete());
  ASSERT_EQ(plan.order, (std::vector<PartId>{plate, peg, block}));
  ASSERT_EQ(plan.precedence.size(), 1u);
  EXPECT_EQ(plan.precedence[0].before, peg);
  EXPECT_EQ(plan.precedence[0].after, block);
  EXPECT_EQ(plan.precedence[0].reason, eval::Precedence::Reason::Blocks);
  EXPECT_NEAR(plan.checkOf(peg)->directions.front().blockers.at(0).distance, 0.003, 2e-5);
  EXPECT_EQ(plan.pairChecks, 1) << "the peg against the block; the plate the peg stands on is behind it on its way up, not swept";

  // The block's way flipped to come up from below the plate: the plate is always there, so nothing puts
  // the block in, and the peg still goes in.
  b.a.constraints[1].homeDirection = -Eigen::Vector3d::UnitZ();
  const eval::SequencePlan stuck = eval::planSequence(b.a);
  EXPECT_FALSE(stuck.complete());
  ASSERT_EQ(stuck.stuck.size(), 1u);
  EXPECT_EQ(stuck.stuck[0].part, block);
  ASSERT_EQ(stuck.stuck[0].blockers.size(), 1u);
  EXPECT_EQ(stuck.stuck[0].blockers[0], (std::vector<PartId>{peg, plate})) << "the peg first, 3 mm below; then the plate";
  EXPECT_EQ(stuck.order, (std::vector<PartId>{plate, peg}));
}
