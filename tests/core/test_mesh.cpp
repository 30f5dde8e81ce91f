#include <gtest/gtest.h>

#include "vaw/mass_properties.hpp"
#include "vaw/mesh.hpp"
#include "vaw/primitives.hpp"

using namespace vaw;

TEST(MeshCheck, PrimitivesAreClosedAndConsistent) {
  for (const TriMesh& m : {primitives::box({1, 2, 3}), primitives::cylinder(1, 2, 17), primitives::tube(2, 1, 1, 9),
                           primitives::sphere(1, 12, 7)}) {
    const MeshCheck c = checkMesh(m);
    EXPECT_TRUE(c.valid()) << c.summary();
    EXPECT_EQ(c.degenerateTriangles, 0u);
    EXPECT_EQ(c.duplicateVertices, 0u);
  }
}

TEST(MeshCheck, MissingTriangleOpensTheMesh) {
  TriMesh m = primitives::box({1, 1, 1});
  m.triangles.pop_back();
  const MeshCheck c = checkMesh(m);
  EXPECT_FALSE(c.closed());
  EXPECT_EQ(c.boundaryEdges, 3u);
  EXPECT_NE(c.summary().find("3 open (boundary) edges"), std::string::npos);
}

TEST(MeshCheck, OneFlippedTriangleIsInconsistent) {
  TriMesh m = primitives::box({1, 1, 1});
  std::swap(m.triangles[0][1], m.triangles[0][2]);
  const MeshCheck c = checkMesh(m);
  EXPECT_TRUE(c.closed());
  EXPECT_FALSE(c.consistentlyOriented());
  EXPECT_EQ(c.inconsistentEdges, 3u);
}

TEST(MeshCheck, NonFiniteAndOutOfRange) {
  TriMesh m = primitives::box({1, 1, 1});
  m.vertices[0].x() = std::numeric_limits<double>::quiet_NaN();
  m.triangles.emplace_back(0, 1, 99);
  const MeshCheck c = checkMesh(m);
  EXPECT_EQ(c.nonFiniteVertices, 1u);
  EXPECT_EQ(c.badIndices, 1u);
  EXPECT_FALSE(c.valid());
}

TEST(Weld, TriangleSoupBecomesClosed) {
  // What an STL file gives: every triangle with its own three corners.
  const TriMesh box = primitives::box({1, 1, 1});
  TriMesh soup;
  for (const auto& t : box.triangles) {
    const int base = static_cast<int>(soup.vertices.size());
    for (int k = 0; k < 3; ++k) soup.vertices.push_back(box.vertices[static_cast<std::size_t>(t[k])] + Eigen::Vector3d::Constant(1e-13 * k));
    soup.triangles.emplace_back(base, base + 1, base + 2);
  }
  EXPECT_FALSE(checkMesh(soup).closed());
  EXPECT_EQ(weldVertices(soup, 1e-9), 36u - 8u);
  EXPECT_EQ(soup.vertices.size(), 8u);
  EXPECT_TRUE(checkMesh(soup).valid());
}

TEST(Weld, KeepsVerticesFartherThanTolerance) {
  TriMesh m;
  m.vertices = {{0, 0, 0}, {2e-9, 0, 0}, {1, 0, 0}};
  m.triangles = {{0, 1, 2}};
  EXPECT_EQ(weldVertices(m, 1e-9), 0u);
  EXPECT_EQ(weldVertices(m, 3e-9), 1u);
}

TEST(Weld, FarOutCoordinatesAreDefined) {
  // A 1e300 box overflowed the integer grid cells (undefined behaviour, reported by UBSan); cells are
  // now clamped and far vertices still weld only by their true distance.
  TriMesh m;
  m.vertices = {{1e300, -1e300, 0}, {1e300, -1e300, 0}, {-1e300, 1e300, 1e300}, {4e18, 0, 0}, {4e18, 1, 0}, {0, 0, 0}};
  m.triangles = {{0, 2, 3}, {1, 4, 5}};
  EXPECT_EQ(weldVertices(m, 1e-9), 1u);  // the two equal corners, nothing else
  EXPECT_EQ(m.vertices.size(), 5u);
  EXPECT_EQ(m.triangles[1][0], 0);
}

TEST(Degenerate, RemovedAndCounted) {
  TriMesh m = primitives::box({1, 1, 1});
  m.triangles.emplace_back(0, 0, 1);  // repeated index
  m.vertices.emplace_back(0.5, 0.5, 0.5);
  m.vertices.emplace_back(1.5, 1.5, 1.5);
  const int a = static_cast<int>(m.vertices.size()) - 2;
  m.vertices.emplace_back(2.5, 2.5, 2.5);
  m.triangles.emplace_back(a, a + 1, a + 2);  // collinear, with no neighbour to mend it into
  EXPECT_EQ(checkMesh(m).degenerateTriangles, 2u);
  const MeshRepair r = repairMesh(m, 0.0, 0.0);
  EXPECT_EQ(r.removed, 2u);
  EXPECT_EQ(r.mended, 0u);
  EXPECT_EQ(m.triangles.size(), 12u);
}

// A mesher that puts a node in the middle of an edge on one face's side only closes the gap with a
// zero-area triangle along that edge. Deleting it by area opens three edges; mending keeps the box closed.
TEST(Degenerate, SliverOnAnEdgeIsMendedAndTheMeshStaysClosed) {
  TriMesh m = primitives::box({1, 1, 1});
  // An edge (a, b) and the triangle t1 = (a, b, x) on one side of it.
  std::size_t t1 = 0;
  int a = m.triangles[0][0], b = m.triangles[0][1], x = m.triangles[0][2];
  ASSERT_TRUE(checkMesh(m).valid());
  const int mid = static_cast<int>(m.vertices.size());
  m.vertices.push_back(0.5 * (m.vertices[static_cast<std::size_t>(a)] + m.vertices[static_cast<std::size_t>(b)]));
  m.triangles[t1] = Eigen::Vector3i(a, mid, x);
  m.triangles.emplace_back(mid, b, x);
  m.triangles.emplace_back(a, b, mid);  // the sliver
  const double volume = integrateVolume(m).volume;
  ASSERT_TRUE(checkMesh(m).closed());
  ASSERT_EQ(checkMesh(m).degenerateTriangles, 1u);

  TriMesh byArea = m;
  std::erase_if(byArea.triangles, [&](const Eigen::Vector3i& t) { return t == Eigen::Vector3i(a, b, mid); });
  EXPECT_EQ(checkMesh(byArea).boundaryEdges, 3u) << "what deleting the sliver by its area did";

  const MeshRepair r = repairMesh(m, 1e-12, 1e-14);
  EXPECT_EQ(r.mended, 1u);
  EXPECT_EQ(r.removed, 0u);
  EXPECT_TRUE(r.check.valid()) << r.check.summary();
  EXPECT_EQ(r.check.degenerateTriangles, 0u);
  EXPECT_NEAR(integrateVolume(m).volume, volume, 1e-15);
  EXPECT_NEAR(volume, 1.0, 1e-15);
}

// A fan of slivers along one edge (three nodes on one side, none on the other) is mended pass by pass.
TEST(Degenerate, FanOfSliversIsMended) {
  TriMesh m = primitives::box({1, 1, 1});
  const int a = m.triangles[0][0], b = m.triangles[0][1], x = m.triangles[0][2];
  const Eigen::Vector3d pa = m.vertices[static_cast<std::size_t>(a)], pb = m.vertices[static_cast<std::size_t>(b)];
  std::vector<int> nodes{a};
  for (const double t : {0.25, 0.5, 0.75}) {
    nodes.push_back(static_cast<int>(m.vertices.size()));
    m.vertices.push_back(pa + t * (pb - pa));
  }
  nodes.push_back(b);
  m.triangles[0] = Eigen::Vector3i(nodes[0], nodes[1], x);
  for (std::size_t k = 1; k + 1 < nodes.size(); ++k) m.triangles.emplace_back(nodes[k], nodes[k + 1], x);
  // Closed by slivers (a, b, n1), (n1, b, n2), (n2, b, n3): each edge a->n1, n1->n2, ... met once each way.
  m.triangles.emplace_back(a, b, nodes[1]);
  m.triangles.emplace_back(nodes[1], b, nodes[2]);
  m.triangles.emplace_back(nodes[2], b, nodes[3]);
  ASSERT_TRUE(checkMesh(m).closed()) << checkMesh(m).summary();
  const MeshRepair r = repairMesh(m, 1e-12, 1e-14);
  EXPECT_EQ(r.mended, 3u);
  EXPECT_TRUE(r.check.valid()) << r.check.summary();
  EXPECT_EQ(r.check.degenerateTriangles, 0u);
  EXPECT_NEAR(integrateVolume(m).volume, 1.0, 1e-15);
}

TEST(TriMesh, AppendAndBounds) {
  TriMesh a = primitives::box({1, 1, 1});
  a.append(primitives::box({1, 1, 1}), Eigen::Isometry3d(Eigen::Translation3d(2, 0, 0)));
  EXPECT_EQ(a.triangles.size(), 24u);
  EXPECT_TRUE(checkMesh(a).valid());
  EXPECT_NEAR(a.bounds().max().x(), 2.5, 1e-15);
  EXPECT_NEAR(a.bounds().min().x(), -0.5, 1e-15);
}

TEST(Primitives, GridBoxIsAClosedBoxOfManyTriangles) {
  const TriMesh m = primitives::gridBox({0.3, 0.2, 0.04}, 7);
  EXPECT_EQ(m.triangleCount(), 12u * 7u * 7u);
  EXPECT_TRUE(checkMesh(m).valid()) << checkMesh(m).summary();
  EXPECT_EQ(checkMesh(m).duplicateVertices, 0u) << "face grids share their edge vertices";
  EXPECT_NEAR(m.bounds().sizes().prod(), 0.3 * 0.2 * 0.04, 1e-15);
}
