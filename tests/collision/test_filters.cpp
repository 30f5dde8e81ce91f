// Filter modes on mesh-mesh queries (the paper's KEEP_COPLANAR, SKIP_COPLANAR, SKIP_COAXIAL, NOCARE).
#include <gtest/gtest.h>

#include <algorithm>
#include <numbers>

#include "collision_test_support.hpp"
#include "vaw/primitives.hpp"

using namespace vaw;
using namespace vaw::collision;
using ctest::at;

namespace {

// A 125 mm cube on the ground and a 62.5 mm cube whose bottom face is `gap` above the big one's top face
// (sizes exact in binary, so that gap 0 is exactly touching).
struct TwoBoxes {
  CollisionWorld world;
  ObjectId big, small;
  explicit TwoBoxes(double gap) : world(make(gap)), big(ObjectId::part(0)), small(ObjectId::part(1)) {}
  static Assembly make(double gap) {
    ctest::SceneBuilder b;
    b.part("big", primitives::box({0.125, 0.125, 0.125}), at(0, 0, 0.0625));
    b.part("small", primitives::box({0.0625, 0.0625, 0.0625}), at(0.01, 0.005, 0.125 + 0.03125 + gap));
    b.base(0);
    return b.a;
  }
};

double maxPenetration(const QueryResult& r) {
  double m = 0.0;
  for (const auto& c : r.contacts) m = std::max(m, c.penetration);
  return m;
}

}  // namespace

// A pair wholly on either side of one's large face, each reaching it, can only touch (the check at rest
// counts it as touching without walking the plate's hierarchy); lifted, sunk into the other, or a bolt
// through it, it is no such pair. (Only a part's four largest faces are tried: a cover on a plate.)
TEST(Filters, APartRestingOnAnotherFaceIsToldFromItsBoxes) {
  const auto world = [](double gap, double boltLength) {
    ctest::SceneBuilder b;
    b.part("plate", primitives::box({0.125, 0.125, 0.02}), at(0, 0, 0.01));
    b.part("cover", primitives::box({0.0625, 0.0625, 0.005}), at(0.01, 0.005, 0.02 + 0.0025 + gap));
    if (boltLength > 0.0) b.part("bolt", primitives::box({0.01, 0.01, boltLength}), at(-0.04, 0, 0.02 - 0.5 * boltLength + 0.005));
    b.base(0);
    return CollisionWorld(b.a);
  };
  const ObjectId plate = ObjectId::part(0), cover = ObjectId::part(1), bolt = ObjectId::part(2);
  EXPECT_TRUE(world(0.0, 0.0).restOnEachOther(cover, plate));
  EXPECT_TRUE(world(0.0, 0.0).restOnEachOther(plate, cover));
  EXPECT_FALSE(world(1e-4, 0.0).restOnEachOther(cover, plate)) << "0.1 mm above: not reaching the face";
  EXPECT_FALSE(world(-1e-3, 0.0).restOnEachOther(cover, plate)) << "1 mm into the plate";
  // The bolt's top 5 mm stand above the plate, its shank down through it.
  EXPECT_FALSE(world(0.0, 0.03).restOnEachOther(bolt, plate));
}

TEST(Filters, ExactlyTouchingFacesUnderEachMode) {
  TwoBoxes t(0.0);
  QueryOptions o;
  o.mode = FilterMode::NoCare;
  const QueryResult plain = t.world.query(t.small, t.big, o);
  ASSERT_FALSE(plain.contacts.empty()) << "FCL reports exactly touching faces as colliding";
  const auto coplanar = std::count_if(plain.contacts.begin(), plain.contacts.end(), [](const Contact& c) { return c.coplanar; });
  EXPECT_GT(coplanar, 0);
  EXPECT_LT(static_cast<std::size_t>(coplanar), plain.contacts.size()) << "the small box's sides touch the top too";
  EXPECT_LE(maxPenetration(plain), 1e-12) << "resting faces and edges only touch";

  o.mode = FilterMode::SkipCoplanar;
  const QueryResult skip = t.world.query(t.small, t.big, o);
  EXPECT_EQ(skip.contacts.size() + static_cast<std::size_t>(coplanar), plain.contacts.size());
  for (const auto& c : skip.contacts) EXPECT_FALSE(c.coplanar);

  o.dropTouching = true;
  EXPECT_TRUE(t.world.query(t.small, t.big, o).contacts.empty()) << "touching-only pairs never block";

  o = {};
  o.mode = FilterMode::KeepCoplanar;
  const QueryResult keep = t.world.query(t.small, t.big, o);
  ASSERT_FALSE(keep.contacts.empty());
  for (const auto& c : keep.contacts) {
    EXPECT_TRUE(c.coplanar);
    EXPECT_NEAR(c.position.z(), 0.125, 1e-12);
  }
}

TEST(Filters, KeepCoplanarCountsAGapWithinTheTolerance) {
  QueryOptions keep;
  keep.mode = FilterMode::KeepCoplanar;
  QueryOptions plain;
  // 5 um: FCL sees no collision, but the faces are coplanar within the 10 um tolerance.
  TwoBoxes t5(5e-6);
  EXPECT_TRUE(t5.world.query(t5.small, t5.big, plain).contacts.empty());
  EXPECT_FALSE(t5.world.query(t5.small, t5.big, keep).contacts.empty());
  // 15 um: beyond the tolerance.
  TwoBoxes t15(15e-6);
  EXPECT_TRUE(t15.world.query(t15.small, t15.big, keep).contacts.empty());
}

TEST(Filters, PenetrationIsTheDepthOfTheCrossing) {
  TwoBoxes t(-1e-3);  // sunk 1 mm into the big box
  QueryOptions o;
  o.mode = FilterMode::SkipCoplanar;
  o.dropTouching = true;
  const QueryResult r = t.world.query(t.small, t.big, o);
  ASSERT_FALSE(r.contacts.empty());
  EXPECT_NEAR(maxPenetration(r), 1e-3, 1e-12);
  for (const auto& c : r.contacts) {
    EXPECT_GT(c.penetration, c.allowance);
    EXPECT_NEAR(c.position.z(), 0.125, 1e-9) << "the crossing lies on the big box's top face";
  }
}

TEST(Filters, SkipCoaxialIgnoresTheSleeveOnItsShaft) {
  Assembly a = ctest::loadBundled("sleeve-on-shaft.vaw.json");
  const PartId sleeve = *a.findPart("sleeve");
  a.parts[sleeve].pose = at(0, 0, 0.100);  // halfway up the shaft
  const CollisionWorld w(a);
  const ObjectId s = ObjectId::part(sleeve), base = ObjectId::part(*a.base);
  QueryOptions o;
  const QueryResult plain = w.query(s, base, o);
  ASSERT_FALSE(plain.contacts.empty()) << "bore and shaft share their vertices: FCL reports them";
  const auto coaxial = std::count_if(plain.contacts.begin(), plain.contacts.end(), [](const Contact& c) { return c.coaxial; });
  EXPECT_GT(coaxial, 0);
  o.mode = FilterMode::SkipCoaxial;
  const QueryResult skip = w.query(s, base, o);
  EXPECT_EQ(skip.contacts.size() + static_cast<std::size_t>(coaxial), plain.contacts.size());
  for (const auto& c : skip.contacts) {
    EXPECT_FALSE(c.coaxial);
    EXPECT_LE(c.penetration, 1e-9) << "(rounding of mm to m) the sleeve's end faces meet the shaft only along their inner edge";
  }
  o.dropTouching = true;
  EXPECT_TRUE(w.query(s, base, o).contacts.empty());
}

TEST(Filters, SkipCoaxialStillSeesAnInterferenceFit) {
  // A bore 0.1 mm smaller than the shaft: not an equal-diameter fit (radius tolerance 0.05 mm).
  ctest::SceneBuilder b;
  b.part("shaft", primitives::cylinder(0.015, 0.2, 64), at(0, 0, 0));
  b.part("sleeve", primitives::tube(0.025, 0.0149, 0.04, 64), at(0, 0, 0.02));
  b.base(0);
  const CollisionWorld w(b.a);
  QueryOptions o;
  o.mode = FilterMode::SkipCoaxial;
  o.dropTouching = true;
  const QueryResult r = w.query(ObjectId::part(1), ObjectId::part(0), o);
  ASSERT_FALSE(r.contacts.empty());
  for (const auto& c : r.contacts) EXPECT_FALSE(c.coaxial);
  EXPECT_GT(maxPenetration(r), 5e-5);
}

TEST(Filters, MisalignedTessellationOfAFitDoesNotBlock) {
  // The same fit turned by half a segment: the shaft's corners poke 17 um (about its 18 um sagitta) into the
  // sleeve's end faces. SKIP_COAXIAL skips a bore's end faces against its shaft; without it, the allowance
  // (tolerance + the shaft's sagitta along the depth) still keeps those pairs a touch.
  Assembly a = ctest::loadBundled("sleeve-on-shaft.vaw.json");
  const PartId sleeve = *a.findPart("sleeve");
  Eigen::Isometry3d p = at(0, 0, 0.100);
  p.rotate(Eigen::AngleAxisd(std::numbers::pi / 64.0, Eigen::Vector3d::UnitZ()));
  a.parts[sleeve].pose = p;
  const CollisionWorld w(a);
  const ObjectId s = ObjectId::part(sleeve), base = ObjectId::part(*a.base);
  QueryOptions o;
  const QueryResult plain = w.query(s, base, o);
  double endFaceDepth = 0.0, endFaceAllowance = 1.0;
  for (const auto& c : plain.contacts)
    if (w.patches(s)->cylinderOf[static_cast<std::size_t>(c.triangleA)] < 0 && c.penetration > endFaceDepth) {
      endFaceDepth = c.penetration;
      endFaceAllowance = c.allowance;
    }
  EXPECT_GT(endFaceDepth, 1e-5) << "deeper than the distance tolerance alone";
  EXPECT_LT(endFaceDepth, endFaceAllowance);
  EXPECT_NEAR(endFaceAllowance, 1e-5 + 0.015 * (1.0 - std::cos(std::numbers::pi / 64.0)), 1e-9);
  o.dropTouching = true;
  const QueryResult dropped = w.query(s, base, o);
  for (const auto& c : dropped.contacts) EXPECT_TRUE(c.coaxial) << "only bore-on-shaft pairs are left";
  o.mode = FilterMode::SkipCoaxial;
  EXPECT_TRUE(w.query(s, base, o).contacts.empty());
}

TEST(Filters, BlockOnBundledPlateRestsOnCoplanarFaces) {
  Assembly a = ctest::loadBundled("block-on-plate.vaw.json");
  const PartId block = *a.findPart("block");
  a.parts[block].pose = *a.parts[block].finalPose;
  const CollisionWorld w(a);
  QueryOptions keep;
  keep.mode = FilterMode::KeepCoplanar;
  const QueryResult r = w.query(ObjectId::part(block), ObjectId::part(*a.base), keep);
  ASSERT_FALSE(r.contacts.empty());
  for (const auto& c : r.contacts) EXPECT_NEAR(c.position.z(), 0.040, 1e-9);
}

TEST(Filters, FineTessellationDoesNotHideADeepCrossing) {
  // The small cube's faces split into 16 x 16 grids (3.9 mm cells): depth is measured to the face's outline,
  // not to each small triangle's edges.
  for (double sink : {1e-3, 1e-2}) {
    ctest::SceneBuilder b;
    b.part("big", primitives::box({0.125, 0.125, 0.125}), at(0, 0, 0.0625));
    b.part("small", primitives::gridBox({0.0625, 0.0625, 0.0625}, 16), at(0.01, 0.005, 0.125 + 0.03125 - sink));
    const CollisionWorld w(b.a);
    QueryOptions o;
    o.dropTouching = true;
    const QueryResult r = w.query(ObjectId::part(1), ObjectId::part(0), o);
    ASSERT_FALSE(r.contacts.empty()) << sink;
    if (sink < 2e-3) EXPECT_NEAR(maxPenetration(r), sink, 1e-9);
    else EXPECT_GT(maxPenetration(r), 2e-3) << "deeper than the tolerance by far (the estimate reaches one grid row back)";
  }
  // Exactly resting, the fine faces only touch.
  ctest::SceneBuilder b;
  b.part("big", primitives::box({0.125, 0.125, 0.125}), at(0, 0, 0.0625));
  b.part("small", primitives::gridBox({0.0625, 0.0625, 0.0625}, 16), at(0.01, 0.005, 0.125 + 0.03125));
  const CollisionWorld w(b.a);
  QueryOptions o;
  const QueryResult r = w.query(ObjectId::part(1), ObjectId::part(0), o);
  ASSERT_FALSE(r.contacts.empty());
  EXPECT_LE(maxPenetration(r), 1e-12);
}
