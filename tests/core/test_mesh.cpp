#include <gtest/gtest.h>

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
  m.triangles.emplace_back(a, a + 1, a + 2);  // collinear
  EXPECT_EQ(checkMesh(m).degenerateTriangles, 2u);
  EXPECT_EQ(removeDegenerateTriangles(m, 0.0), 2u);
  EXPECT_EQ(m.triangles.size(), 12u);
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
