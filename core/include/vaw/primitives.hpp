#pragma once
// Closed, outward-oriented tessellations of the solids a scene file may name instead of a mesh file.
// Each is centred on its own frame's origin; cylinders and tubes run along +z.
#include "vaw/mesh.hpp"

namespace vaw::primitives {

TriMesh box(const Eigen::Vector3d& size);
// A box whose every face is an n x n grid (12 n^2 triangles): a large flat face made of many small
// triangles, as CAD exports tessellate them (tests and benchmarks of coplanar contact).
TriMesh gridBox(const Eigen::Vector3d& size, int n);
TriMesh cylinder(double radius, double height, int segments);
TriMesh tube(double outerRadius, double innerRadius, double height, int segments);
TriMesh sphere(double radius, int segments, int rings);

}  // namespace vaw::primitives
