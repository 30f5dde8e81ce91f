// Bad geometry is named in the world's diagnostics and never crashes a query.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <memory>

#include "collision_test_support.hpp"
#include "vaw/collision/time_of_impact.hpp"
#include "vaw/primitives.hpp"

using namespace vaw;
using namespace vaw::collision;
using ctest::at;

namespace {

const Diagnostic* find(const Diagnostics& d, const std::string& field) {
  auto it = std::find_if(d.begin(), d.end(), [&](const Diagnostic& x) { return x.field == field; });
  return it == d.end() ? nullptr : &*it;
}

// A sound 100 mm cube as the base and `bad` as a part resting on it (plus a mate of its bottom face), then
// every query the world offers on it.
struct Probe {
  Assembly a;
  explicit Probe(TriMesh bad) {
    ctest::SceneBuilder b;
    b.part("floor", primitives::box({0.1, 0.1, 0.1}), at(0, 0, -0.05));
    // Mass properties of a broken mesh are meaningless; give the part a valid set so the world can be built.
    b.part("bad", primitives::box({0.02, 0.02, 0.02}), at(0, 0, 0.01));
    b.a.parts[1].mesh = std::make_shared<const TriMesh>(std::move(bad));
    b.base(0);
    b.mate(1, {0, 0, -0.01}, {0, 0, -1}, {0, 0, 0.05}, {0, 0, 1});  // the floor's top, in its frame
    a = b.a;
  }
  void exercise(const CollisionWorld& w) const {
    const ObjectId bad = ObjectId::part(1), floor = ObjectId::part(0);
    for (FilterMode m : {FilterMode::NoCare, FilterMode::KeepCoplanar, FilterMode::SkipCoplanar, FilterMode::SkipCoaxial}) {
      QueryOptions o;
      o.mode = m;
      (void)w.query(bad, floor, o);
      (void)w.query(floor, bad, o);
    }
    (void)w.queryAll(bad);
    (void)w.distance(bad, floor);
    const Support s = w.support(a.constraints[0]);
    (void)w.touching(s);
    (void)w.blocked(s);
    (void)w.colliding(bad, w.pose(bad));
    (void)firstEventOnBase(w, s, translation(w.pose(bad), Eigen::Vector3d::UnitX(), 0.01));
    (void)timeOfImpact(w, bad, translation(w.pose(bad), Eigen::Vector3d::UnitZ(), 0.01));
  }
};

}  // namespace

TEST(BadGeometry, DegenerateTrianglesAreLeftOutWithAWarning) {
  TriMesh m = primitives::box({0.02, 0.02, 0.02});
  m.triangles.emplace_back(0, 0, 1);  // repeated index
  m.vertices.emplace_back(0.0, 0.0, 0.0);
  m.vertices.emplace_back(0.005, 0.0, 0.0);
  m.vertices.emplace_back(0.01, 0.0, 0.0);
  const int n = static_cast<int>(m.vertices.size());
  m.triangles.emplace_back(n - 3, n - 2, n - 1);  // collinear corners
  Probe p(m);
  const CollisionWorld w(p.a);
  const Diagnostic* d = find(w.diagnostics(), "collision.degenerate-triangles");
  ASSERT_NE(d, nullptr);
  EXPECT_EQ(d->severity, Diagnostic::Severity::Warning);
  EXPECT_NE(d->file.find("bad"), std::string::npos) << "names the object";
  EXPECT_NE(d->found.find("2 degenerate"), std::string::npos) << d->message();
  EXPECT_EQ(w.info(ObjectId::part(1)).triangles, 12u);
  p.exercise(w);
  // Still a working box: its bottom face rests on the floor.
  EXPECT_TRUE(w.touching(w.support(p.a.constraints[0])).touching) << w.touching(w.support(p.a.constraints[0])).reason << " / " << w.support(p.a.constraints[0]).problem;
}

// A mesh's hierarchy is built once while the mesh lives and taken by every later world: each still reports
// what is wrong with the mesh, naming its own part, and a mesh equal to a freed one is built anew.
TEST(BadGeometry, AMeshTakenFromAnEarlierWorldIsReportedAsItsOwn) {
  TriMesh m = primitives::box({0.02, 0.02, 0.02});
  m.triangles.pop_back();
  Probe p(m);
  const auto first = std::make_unique<CollisionWorld>(p.a);
  ASSERT_NE(find(first->diagnostics(), "collision.open-mesh"), nullptr);
  Assembly renamed = p.a;
  renamed.parts[1].name = "renamed";
  const CollisionWorld second(renamed);
  const Diagnostic* d = find(second.diagnostics(), "collision.open-mesh");
  ASSERT_NE(d, nullptr);
  EXPECT_EQ(d->file, "part \"renamed\"");
  EXPECT_EQ(d->found, find(first->diagnostics(), "collision.open-mesh")->found);
  EXPECT_EQ(second.info(ObjectId::part(1)).triangles, first->info(ObjectId::part(1)).triangles);
  p.exercise(second);
  // The same triangles in a new mesh of another shape: its own hierarchy, its own (here: no) warning.
  Assembly closed = p.a;
  closed.parts[1].mesh = std::make_shared<const TriMesh>(primitives::box({0.02, 0.02, 0.02}));
  const CollisionWorld third(closed);
  EXPECT_EQ(find(third.diagnostics(), "collision.open-mesh"), nullptr);
  EXPECT_EQ(third.info(ObjectId::part(1)).triangles, 12u);
}

// The meshes of a world are built side by side on the machine's cores: what each reports still comes in the
// parts' order, and parts with equal meshes still share one build.
TEST(BadGeometry, MeshesBuiltSideBySideReportInThePartsOrder) {
  ctest::SceneBuilder b;
  b.part("floor", primitives::box({1.0, 1.0, 0.1}), at(0, 0, -0.05));
  const int n = 12;
  for (int i = 0; i < n; ++i) {
    // Each a mesh of its own size (so nothing is shared), every third missing a triangle; the largest last,
    // so that the builds finish out of order.
    const double side = 0.01 + 0.001 * i;
    TriMesh m = i == n - 1 ? primitives::cylinder(0.02, 0.05, 4000) : primitives::box({side, side, side});
    if (i % 3 == 0) m.triangles.pop_back();
    b.part("p" + std::to_string(i), primitives::box({side, side, side}), at(-0.4 + 0.07 * i, 0, side / 2));
    b.a.parts.back().mesh = std::make_shared<const TriMesh>(std::move(m));
  }
  // Two more with one mesh between them: built once.
  const auto shared = std::make_shared<const TriMesh>(primitives::box({0.031, 0.031, 0.031}));
  b.part("twin-a", primitives::box({0.031, 0.031, 0.031}), at(0, 0.3, 0.0155));
  b.a.parts.back().mesh = shared;
  b.part("twin-b", primitives::box({0.031, 0.031, 0.031}), at(0.1, 0.3, 0.0155));
  b.a.parts.back().mesh = std::make_shared<const TriMesh>(*shared);
  b.base(0);
  const CollisionWorld w(b.a);
  std::vector<std::string> open;
  for (const Diagnostic& d : w.diagnostics())
    if (d.field == "collision.open-mesh") open.push_back(d.file);
  std::vector<std::string> expected;
  for (int i = 0; i < n; i += 3) expected.push_back("part \"p" + std::to_string(i) + "\"");
  EXPECT_EQ(open, expected);
  for (int i = 0; i < n; ++i) {
    const auto id = ObjectId::part(static_cast<PartId>(i + 1));
    EXPECT_EQ(w.info(id).proxy, ProxyKind::Mesh) << i;
    EXPECT_EQ(w.info(id).triangles, b.a.parts[static_cast<std::size_t>(i + 1)].mesh->triangles.size()) << i;
  }
  EXPECT_EQ(w.info(ObjectId::part(n + 2)).proxyReason, "full mesh, shared with part \"twin-a\"");
  // Every part collides where it stands: a part sunk 1 mm into the floor meets it.
  QueryOptions o;
  o.dropTouching = true;
  for (int i = 0; i < n; i += 4) {
    const auto id = ObjectId::part(static_cast<PartId>(i + 1));
    Eigen::Isometry3d sunk = w.pose(id);
    sunk.translation().z() -= 0.001;
    EXPECT_FALSE(w.query(id, sunk, ObjectId::part(0), o).contacts.empty()) << i;
  }
}

TEST(BadGeometry, OpenMeshIsWarnedAndStillCollides) {
  TriMesh m = primitives::box({0.02, 0.02, 0.02});
  m.triangles.pop_back();  // one triangle of the top face missing
  Probe p(m);
  const CollisionWorld w(p.a);
  const Diagnostic* d = find(w.diagnostics(), "collision.open-mesh");
  ASSERT_NE(d, nullptr);
  EXPECT_EQ(d->severity, Diagnostic::Severity::Warning);
  EXPECT_NE(d->found.find("3 open edges"), std::string::npos) << d->message();
  p.exercise(w);
  // Sunk 1 mm into the floor it collides (surface test: the missing triangle is on top).
  QueryOptions o;
  o.dropTouching = true;
  const QueryResult r = w.query(ObjectId::part(1), at(0, 0, 0.009), ObjectId::part(0), o);
  ASSERT_FALSE(r.contacts.empty());
  double deepest = 0.0;
  for (const auto& c : r.contacts) deepest = std::max(deepest, c.penetration);
  EXPECT_NEAR(deepest, 1e-3, 1e-9);
}

TEST(BadGeometry, DuplicatedVerticesAreWarnedAndMergedForNeighbours) {
  // Triangle soup, as an STL file gives it: every triangle has its own three vertices.
  const TriMesh box = primitives::box({0.02, 0.02, 0.02});
  TriMesh soup;
  for (const auto& t : box.triangles) {
    const int base = static_cast<int>(soup.vertices.size());
    for (int k = 0; k < 3; ++k) soup.vertices.push_back(box.vertices[static_cast<std::size_t>(t[k])]);
    soup.triangles.emplace_back(base, base + 1, base + 2);
  }
  Probe p(soup);
  const CollisionWorld w(p.a);
  const Diagnostic* d = find(w.diagnostics(), "collision.duplicate-vertices");
  ASSERT_NE(d, nullptr);
  EXPECT_NE(d->found.find("28 duplicated"), std::string::npos) << d->message();
  EXPECT_EQ(find(w.diagnostics(), "collision.open-mesh"), nullptr) << "welded, the soup is closed";
  EXPECT_EQ(w.patches(ObjectId::part(1))->planes.size(), 6u);
  p.exercise(w);
  EXPECT_TRUE(w.touching(w.support(p.a.constraints[0])).touching) << w.touching(w.support(p.a.constraints[0])).reason << " / " << w.support(p.a.constraints[0]).problem;
}

TEST(BadGeometry, NonFiniteVerticesAndBadIndicesAreInvalidTriangles) {
  TriMesh m = primitives::box({0.02, 0.02, 0.02});
  m.vertices.emplace_back(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0);
  const int nan = static_cast<int>(m.vertices.size()) - 1;
  m.triangles.emplace_back(0, 1, nan);
  m.triangles.emplace_back(0, 1, 1000);
  m.triangles.emplace_back(-1, 1, 2);
  Probe p(m);
  const CollisionWorld w(p.a);
  const Diagnostic* d = find(w.diagnostics(), "collision.degenerate-triangles");
  ASSERT_NE(d, nullptr);
  EXPECT_NE(d->found.find("3 degenerate or invalid"), std::string::npos) << d->message();
  EXPECT_TRUE(w.worldBounds(ObjectId::part(1)).max().allFinite());
  p.exercise(w);
}

TEST(BadGeometry, MeshWithNoValidTriangleIsAnErrorAndTakesNoPart) {
  for (int variant = 0; variant < 3; ++variant) {
    TriMesh m;
    if (variant == 1) {  // only degenerate triangles
      m.vertices = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
      m.triangles = {{0, 1, 2}, {0, 0, 0}};
    } else if (variant == 2) {  // only NaN
      m.vertices = {{std::numeric_limits<double>::quiet_NaN(), 0, 0}, {1, 0, 0}, {0, 1, 0}};
      m.triangles = {{0, 1, 2}};
    }
    Probe p(m);
    const CollisionWorld w(p.a);
    const Diagnostic* d = find(w.diagnostics(), "collision.no-geometry");
    ASSERT_NE(d, nullptr) << variant;
    EXPECT_EQ(d->severity, Diagnostic::Severity::Error);
    EXPECT_EQ(w.info(ObjectId::part(1)).proxy, ProxyKind::None);
    EXPECT_EQ(w.patches(ObjectId::part(1)), nullptr);
    p.exercise(w);
    EXPECT_TRUE(w.query(ObjectId::part(1), ObjectId::part(0)).contacts.empty());
    EXPECT_FALSE(w.support(p.a.constraints[0]).problem.empty());
  }
}

TEST(BadGeometry, NullMeshIsAnError) {
  Probe p(TriMesh{});
  p.a.parts[1].mesh.reset();
  const CollisionWorld w(p.a);
  ASSERT_NE(find(w.diagnostics(), "collision.no-geometry"), nullptr);
  p.exercise(w);
}

TEST(BadGeometry, ClassifyingGarbageNeverThrows) {
  TriMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {std::numeric_limits<double>::infinity(), 0, 0}};
  m.triangles = {{0, 1, 2}, {0, 1, 2}, {0, 2, 1}, {0, 1, 3}, {0, 1, 4}, {7, 8, 9}, {1, 1, 1}};
  SurfacePatches sp;
  ASSERT_NO_THROW(sp = classifySurfaces(m));
  EXPECT_EQ(sp.degenerateTriangles, 3u);
  EXPECT_GT(sp.nonManifoldEdges, 0u) << "edge 0-1 is used by four triangles";
}
