#pragma once
// The planar and cylindrical pieces of a rigid mesh's surface, found once when the mesh is loaded
// (docs/collision.md, "Surface patches"). The filter modes decide per triangle pair from them whether
// two faces are coplanar (KEEP_COPLANAR / SKIP_COPLANAR) or two cylinders are an equal-diameter coaxial
// fit (SKIP_COAXIAL), and the touching check reads a support face's outline from them.
// Everything here is in the mesh's own frame, metres.
#include <Eigen/Geometry>
#include <cstddef>
#include <vector>

#include "vaw/mesh.hpp"

namespace vaw {
struct CadSolid;
}

namespace vaw::collision {

struct PatchOptions {
  // A planar patch: connected triangles whose normals are within angleTolerance of the first one's and
  // whose vertices lie within distanceTolerance of its plane.
  double distanceTolerance = 1e-6;  // m
  double angleTolerance = 1e-4;     // rad
  // A cylindrical patch: connected planar facets whose shared edges are parallel to one axis, turning by at
  // most maxFacetTurn from facet to facet (a cylinder of 13 or more segments; a hexagon is not a
  // cylinder), at least minFacets of them, all vertices within distanceTolerance (or 1e-6 of the radius,
  // whichever is larger) of the fitted circle, and all facets facing the same way (away from the axis for
  // a shaft, towards it for a bore).
  double maxFacetTurn = 0.5;  // rad
  int minFacets = 3;
  double weldTolerance = 1e-9;  // m: vertices closer than this are one vertex when finding neighbours
};

// One boundary loop of a planar patch in the patch's 2-D coordinates (u, v); collinear vertices merged.
using Outline = std::vector<Eigen::Vector2d>;

struct PlanarPatch {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // unit, pointing out of the solid
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();   // area-weighted centroid, on the plane
  Eigen::Vector3d u = Eigen::Vector3d::UnitX();       // in-plane basis, u x v = normal
  Eigen::Vector3d v = Eigen::Vector3d::UnitY();
  std::vector<int> triangles;
  double area = 0.0;       // m^2
  double residual = 0.0;   // m, largest distance of a vertex from the plane
  std::vector<Outline> outline;  // boundary loops (outer and holes), (u, v) about origin
  Outline hull;                  // convex hull of the outline, counter-clockwise about normal
  // Cylindrical patches this face ends: it borders them, is perpendicular to their axis and lies on their
  // material's side of the radius (outside a bore, like a sleeve's end face; inside a shaft, like its cap).
  // Against an equal coaxial cylinder such a face can only touch along the rim (SKIP_COAXIAL skips it).
  std::vector<int> rimOf;

  [[nodiscard]] double offset() const { return normal.dot(origin); }  // plane: normal . x = offset
  [[nodiscard]] Eigen::Vector3d toMesh(const Eigen::Vector2d& p) const { return origin + p.x() * u + p.y() * v; }
};

struct CylindricalPatch {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();      // on the axis, at the patch's lower axial end
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ(); // unit
  double radius = 0.0;    // m, of the circle through the vertices
  double length = 0.0;    // m, axial extent from `point`
  bool convex = true;     // true: material inside (a shaft, the outside of a tube); false: a bore
  double sagitta = 0.0;   // m, largest distance between a facet and the true cylinder (tessellation error)
  double residual = 0.0;  // m, largest |distance of a vertex from the axis - radius|
  double coverage = 0.0;  // rad of arc covered by the facets (2 pi for a full cylinder)
  std::vector<int> facets;     // planar patch indices
  std::vector<int> triangles;
};

struct SurfacePatches {
  std::vector<PlanarPatch> planes;
  std::vector<CylindricalPatch> cylinders;
  std::vector<int> planeOf;               // per triangle: its planar patch, -1 for a degenerate or invalid one
  std::vector<int> cylinderOf;            // per triangle: its cylindrical patch or -1
  // The largest flat faces (at most kLargestPlanes, none a cylinder's facet), largest first: the planes a
  // part rests or slides on, which the queries try as separating planes (docs/collision.md).
  std::vector<int> largestPlanes;
  static constexpr std::size_t kLargestPlanes = 4;
  // Per triangle: a facet of a CAD face that is neither a plane nor a cylinder (a cone, a torus, a free-form
  // face), which lies up to the tessellation's deflection inside the true surface; empty without CAD faces.
  std::vector<char> curved;
  std::vector<Eigen::Vector3d> normals;   // per triangle, unit (zero for a degenerate one)
  // Per triangle, bit k set: its edge from corner k to corner k+1 lies on its planar patch's outline (the
  // other edges are inside a flat face and do not end it).
  std::vector<unsigned char> outlineEdges;
  std::size_t degenerateTriangles = 0;    // zero area, repeated or out-of-range indices, non-finite corners
  std::size_t boundaryEdges = 0;          // edges with one triangle: the mesh is open
  std::size_t nonManifoldEdges = 0;       // edges with more than two triangles
  std::size_t duplicateVertices = 0;      // vertices at the position of another (merged for neighbours)
  PatchOptions options;
};

// Classifies every triangle once. Never throws on bad geometry: degenerate triangles get no patch and are
// counted; open or non-manifold edges end patches and are counted.
SurfacePatches classifySurfaces(const TriMesh& mesh, const PatchOptions& options = {});
// The same for a CAD part (docs/collision.md, "Surface patches"): the cylinders are the exact cylindrical
// faces the importer classified (`cad`'s faces, split faces already merged) rather than ones found again in
// the triangles, which a cylinder split into quarters or tessellated coarsely can hide. Used when `mesh` is
// the solid's own tessellation (same triangles in the same order); otherwise, or with a null `cad`, the
// cylinders are found in the triangles as above.
SurfacePatches classifySurfaces(const TriMesh& mesh, const CadSolid* cad, const PatchOptions& options = {});

}  // namespace vaw::collision
