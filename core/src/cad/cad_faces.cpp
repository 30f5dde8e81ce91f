#include "vaw/cad_faces.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

namespace vaw {

namespace {

struct UnionFind {
  std::vector<std::size_t> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), std::size_t{0}); }
  std::size_t find(std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  // The smaller index stays the root, so a group keeps its first face's geometry.
  void join(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

bool sameCylinder(const CadFace& a, const CadFace& b, const FaceMergeTolerances& tol) {
  if (a.convex != b.convex || std::abs(a.radius - b.radius) > tol.distance) return false;
  const Eigen::Vector3d u = a.direction.normalized(), v = b.direction.normalized();
  if (u.cross(v).norm() > tol.angle) return false;
  const Eigen::Vector3d rel = b.point - a.point;
  return (rel - u * u.dot(rel)).norm() <= tol.distance;
}

// One cone: apexes, axes (both the way it widens) and half angles alike.
bool sameCone(const CadFace& a, const CadFace& b, const FaceMergeTolerances& tol) {
  if (a.convex != b.convex || std::abs(a.halfAngle - b.halfAngle) > tol.angle) return false;
  if (a.direction.normalized().dot(b.direction.normalized()) < std::cos(tol.angle)) return false;
  return (b.point - a.point).norm() <= tol.distance;
}

bool samePlane(const CadFace& a, const CadFace& b, const FaceMergeTolerances& tol) {
  const Eigen::Vector3d n = a.direction.normalized();
  if (n.dot(b.direction.normalized()) < std::cos(tol.angle)) return false;
  return std::abs(n.dot(b.point - a.point)) <= tol.distance;
}

}  // namespace

std::size_t mergeSplitFaces(CadSolid& solid, const FaceMergeTolerances& tol) {
  const std::size_t n = solid.faces.size();
  UnionFind groups(n);
  // Cylinders by radius, so that only those within the radius tolerance of each other are compared (a
  // plate with a thousand holes of a few sizes).
  std::vector<std::size_t> cylinders, planes, cones;
  for (std::size_t i = 0; i < n; ++i) {
    if (solid.faces[i].surface == CadFace::Surface::Cylinder) cylinders.push_back(i);
    if (solid.faces[i].surface == CadFace::Surface::Plane) planes.push_back(i);
    if (solid.faces[i].surface == CadFace::Surface::Cone) cones.push_back(i);
  }
  // Cones are few (countersinks, chamfers, drill points): every pair.
  for (std::size_t x = 0; x < cones.size(); ++x)
    for (std::size_t y = x + 1; y < cones.size(); ++y)
      if (sameCone(solid.faces[cones[x]], solid.faces[cones[y]], tol)) groups.join(cones[x], cones[y]);
  std::sort(cylinders.begin(), cylinders.end(),
            [&](std::size_t a, std::size_t b) { return solid.faces[a].radius < solid.faces[b].radius; });
  for (std::size_t x = 0; x < cylinders.size(); ++x)
    for (std::size_t y = x + 1; y < cylinders.size(); ++y) {
      const CadFace& a = solid.faces[cylinders[x]];
      const CadFace& b = solid.faces[cylinders[y]];
      if (b.radius - a.radius > tol.distance) break;
      if (sameCylinder(a, b, tol)) groups.join(cylinders[x], cylinders[y]);
    }
  // Planes by offset along their normal's largest component, the same idea.
  const auto key = [&](std::size_t i) {
    const CadFace& f = solid.faces[i];
    return f.direction.normalized().dot(f.point);
  };
  std::sort(planes.begin(), planes.end(), [&](std::size_t a, std::size_t b) { return key(a) < key(b); });
  for (std::size_t x = 0; x < planes.size(); ++x)
    for (std::size_t y = x + 1; y < planes.size(); ++y) {
      // Parallel planes with the same normal that are one plane have the same key to within tol.distance.
      if (key(planes[y]) - key(planes[x]) > tol.distance) break;
      if (samePlane(solid.faces[planes[x]], solid.faces[planes[y]], tol)) groups.join(planes[x], planes[y]);
    }

  std::vector<std::vector<std::size_t>> members(n);
  for (std::size_t i = 0; i < n; ++i) members[groups.find(i)].push_back(i);
  std::size_t merged = 0;
  for (const auto& m : members) merged += m.empty() ? 0 : m.size() - 1;
  if (merged == 0) return 0;

  std::vector<CadFace> faces;
  std::vector<Eigen::Vector3i> triangles;
  triangles.reserve(solid.mesh.triangles.size());
  for (std::size_t root = 0; root < n; ++root) {
    const auto& group = members[root];
    if (group.empty()) continue;
    CadFace f = solid.faces[root];
    f.firstTriangle = triangles.size();
    f.area = 0.0;
    const Eigen::Vector3d u = f.direction.normalized();
    for (const std::size_t i : group) {
      const CadFace& g = solid.faces[i];
      f.area += g.area;
      f.fromSpline = f.fromSpline || g.fromSpline;
      if ((f.surface == CadFace::Surface::Cylinder || f.surface == CadFace::Surface::Cone) && i != root) {
        // g's extent along the first face's axis, from the first face's axis point.
        const double s = g.direction.normalized().dot(u) >= 0.0 ? 1.0 : -1.0;
        const double shift = u.dot(g.point - f.point);
        const double a = shift + s * g.axialMin, b = shift + s * g.axialMax;
        f.axialMin = std::min({f.axialMin, a, b});
        f.axialMax = std::max({f.axialMax, a, b});
      }
      if (f.surface == CadFace::Surface::Cone) f.radius = std::max(f.radius, g.radius);
      for (std::size_t t = g.firstTriangle; t < g.firstTriangle + g.triangleCount && t < solid.mesh.triangles.size(); ++t)
        triangles.push_back(solid.mesh.triangles[t]);
    }
    f.triangleCount = triangles.size() - f.firstTriangle;
    faces.push_back(f);
  }
  // Triangles no face claimed (none in a well-formed solid) stay, at the end.
  std::vector<bool> claimed(solid.mesh.triangles.size(), false);
  for (const CadFace& g : solid.faces)
    for (std::size_t t = g.firstTriangle; t < g.firstTriangle + g.triangleCount && t < claimed.size(); ++t) claimed[t] = true;
  for (std::size_t t = 0; t < claimed.size(); ++t)
    if (!claimed[t]) triangles.push_back(solid.mesh.triangles[t]);
  solid.faces = std::move(faces);
  solid.mesh.triangles = std::move(triangles);
  return merged;
}

}  // namespace vaw
