#include "vaw/collision/surface_patches.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <deque>
#include <numbers>
#include <unordered_map>

#include "geometry2d.hpp"
#include "vaw/importer.hpp"

namespace vaw::collision {

namespace {

constexpr double kPi = std::numbers::pi;

using geom2::perpendicular;

struct Topology {
  TriMesh welded;                        // same triangle order, merged vertex ids
  std::vector<Eigen::Vector3i> neighbour;  // per triangle, across edge k (k -> k+1): -1 if none / non-manifold
  std::vector<char> valid;
};

std::uint64_t edgeKey(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(std::min(a, b))) << 32) |
         static_cast<std::uint32_t>(std::max(a, b));
}

Topology buildTopology(const TriMesh& mesh, const PatchOptions& o, SurfacePatches& out) {
  Topology t;
  t.welded = mesh;
  out.duplicateVertices = weldVertices(t.welded, o.weldTolerance);
  const std::size_t n = mesh.triangles.size();
  t.valid.assign(n, 0);
  out.normals.assign(n, Eigen::Vector3d::Zero());
  const auto nv = static_cast<int>(mesh.vertices.size());
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3i& tri = mesh.triangles[i];
    bool ok = true;
    for (int k = 0; k < 3; ++k) ok = ok && tri[k] >= 0 && tri[k] < nv && mesh.vertices[static_cast<std::size_t>(tri[k])].allFinite();
    if (ok) {
      const Eigen::Vector3i& w = t.welded.triangles[i];
      ok = w[0] != w[1] && w[1] != w[2] && w[0] != w[2];
    }
    if (ok) {
      const Eigen::Vector3d& a = mesh.vertices[static_cast<std::size_t>(tri[0])];
      const Eigen::Vector3d& b = mesh.vertices[static_cast<std::size_t>(tri[1])];
      const Eigen::Vector3d& c = mesh.vertices[static_cast<std::size_t>(tri[2])];
      const Eigen::Vector3d cr = (b - a).cross(c - a);
      const double longest = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
      ok = cr.norm() > 1e-12 * longest && longest > 0.0;
      if (ok) out.normals[i] = cr.normalized();
    }
    t.valid[i] = ok ? 1 : 0;
    if (!ok) ++out.degenerateTriangles;
  }
  // Edge -> triangles by sorting (deterministic, no hashing order).
  struct E { std::uint64_t key; int tri; int k; };
  std::vector<E> edges;
  edges.reserve(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    if (!t.valid[i]) continue;
    const Eigen::Vector3i& w = t.welded.triangles[i];
    for (int k = 0; k < 3; ++k) edges.push_back({edgeKey(w[k], w[(k + 1) % 3]), static_cast<int>(i), k});
  }
  std::sort(edges.begin(), edges.end(), [](const E& a, const E& b) { return a.key != b.key ? a.key < b.key : a.tri < b.tri; });
  t.neighbour.assign(n, Eigen::Vector3i::Constant(-1));
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j].key == edges[i].key) ++j;
    if (j - i == 2) {
      t.neighbour[static_cast<std::size_t>(edges[i].tri)][edges[i].k] = edges[i + 1].tri;
      t.neighbour[static_cast<std::size_t>(edges[i + 1].tri)][edges[i + 1].k] = edges[i].tri;
    } else if (j - i == 1) {
      ++out.boundaryEdges;
    } else {
      ++out.nonManifoldEdges;
    }
    i = j;
  }
  return t;
}

const Eigen::Vector3d& vertexOf(const TriMesh& m, int tri, int k) {
  return m.vertices[static_cast<std::size_t>(m.triangles[static_cast<std::size_t>(tri)][k])];
}

double triangleArea(const TriMesh& m, int tri) {
  const Eigen::Vector3d& a = vertexOf(m, tri, 0);
  return 0.5 * (vertexOf(m, tri, 1) - a).cross(vertexOf(m, tri, 2) - a).norm();
}

// Boundary loops of a planar patch from its triangles' directed edges that have no neighbour in the patch.
std::vector<Outline> outlineOf(const PlanarPatch& p, int index, const Topology& topo, const std::vector<int>& planeOf,
                               double mergeDistance) {
  struct DirEdge { int from, to; };
  std::vector<DirEdge> boundary;
  for (int tri : p.triangles) {
    const Eigen::Vector3i& w = topo.welded.triangles[static_cast<std::size_t>(tri)];
    for (int k = 0; k < 3; ++k) {
      const int nb = topo.neighbour[static_cast<std::size_t>(tri)][k];
      if (nb < 0 || planeOf[static_cast<std::size_t>(nb)] != index) boundary.push_back({w[k], w[(k + 1) % 3]});
    }
  }
  std::sort(boundary.begin(), boundary.end(), [](const DirEdge& a, const DirEdge& b) {
    return a.from != b.from ? a.from < b.from : a.to < b.to;
  });
  std::vector<char> used(boundary.size(), 0);
  auto findFrom = [&](int v) -> std::ptrdiff_t {
    auto it = std::lower_bound(boundary.begin(), boundary.end(), v, [](const DirEdge& e, int x) { return e.from < x; });
    for (; it != boundary.end() && it->from == v; ++it)
      if (!used[static_cast<std::size_t>(it - boundary.begin())]) return it - boundary.begin();
    return -1;
  };
  std::vector<Outline> loops;
  for (std::size_t s = 0; s < boundary.size(); ++s) {
    if (used[s]) continue;
    std::vector<int> chain;
    std::ptrdiff_t e = static_cast<std::ptrdiff_t>(s);
    const int start = boundary[s].from;
    while (e >= 0) {
      used[static_cast<std::size_t>(e)] = 1;
      chain.push_back(boundary[static_cast<std::size_t>(e)].from);
      const int next = boundary[static_cast<std::size_t>(e)].to;
      if (next == start) break;
      e = findFrom(next);
    }
    Outline loop;
    loop.reserve(chain.size());
    for (int v : chain) {
      const Eigen::Vector3d d = topo.welded.vertices[static_cast<std::size_t>(v)] - p.origin;
      loop.emplace_back(d.dot(p.u), d.dot(p.v));
    }
    loop = geom2::mergeCollinear(loop, mergeDistance);
    if (loop.size() >= 2) loops.push_back(std::move(loop));
  }
  return loops;
}

void fitPlane(PlanarPatch& p, const TriMesh& mesh, const SurfacePatches& out) {
  Eigen::Vector3d nsum = Eigen::Vector3d::Zero(), csum = Eigen::Vector3d::Zero();
  double area = 0.0;
  for (int tri : p.triangles) {
    const double a = triangleArea(mesh, tri);
    nsum += a * out.normals[static_cast<std::size_t>(tri)];
    csum += a * (vertexOf(mesh, tri, 0) + vertexOf(mesh, tri, 1) + vertexOf(mesh, tri, 2)) / 3.0;
    area += a;
  }
  p.area = area;
  p.normal = nsum.norm() > 0.0 ? nsum.normalized() : out.normals[static_cast<std::size_t>(p.triangles.front())];
  p.origin = area > 0.0 ? Eigen::Vector3d(csum / area) : vertexOf(mesh, p.triangles.front(), 0);
  p.u = perpendicular(p.normal);
  p.v = p.normal.cross(p.u);
  double residual = 0.0;
  for (int tri : p.triangles)
    for (int k = 0; k < 3; ++k) residual = std::max(residual, std::abs(p.normal.dot(vertexOf(mesh, tri, k) - p.origin)));
  p.residual = residual;
}

// Circle through 2-D points by the algebraic (Kasa) least-squares fit, centred on the mean for
// conditioning. Exact for points on a circle.
bool fitCircle(const std::vector<Eigen::Vector2d>& pts, Eigen::Vector2d& centre, double& radius) {
  if (pts.size() < 3) return false;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& q : pts) mean += q;
  mean /= static_cast<double>(pts.size());
  Eigen::MatrixXd A(static_cast<Eigen::Index>(pts.size()), 3);
  Eigen::VectorXd b(static_cast<Eigen::Index>(pts.size()));
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const Eigen::Vector2d q = pts[i] - mean;
    const auto r = static_cast<Eigen::Index>(i);
    A(r, 0) = q.x();
    A(r, 1) = q.y();
    A(r, 2) = 1.0;
    b(r) = -q.squaredNorm();
  }
  const Eigen::Vector3d s = A.colPivHouseholderQr().solve(b);
  if (!s.allFinite()) return false;
  const Eigen::Vector2d c(-s(0) / 2.0, -s(1) / 2.0);
  const double r2 = c.squaredNorm() - s(2);
  if (!(r2 > 0.0)) return false;
  centre = c + mean;
  radius = std::sqrt(r2);
  return true;
}

struct PatchEdge { int other; int a, b; };  // a neighbouring planar patch across the welded edge (a, b)

// A CAD solid's cylinders (its exact faces, already merged across splits) as patches: the facets are the
// planar patches of the face's triangles, the axis, radius and side the CAD system's. Triangle ranges that
// do not fit the mesh are skipped, so a mesh that is not the solid's own tessellation gets no cylinder.
void cylindersFromCad(const CadSolid& cad, const Topology& topo, SurfacePatches& out, std::vector<int>& cylOfPlane) {
  const auto& wv = topo.welded.vertices;
  for (const CadFace& f : cad.faces) {
    if (f.surface != CadFace::Surface::Cylinder || f.triangleCount == 0 || !(f.radius > 0.0)) continue;
    if (f.firstTriangle + f.triangleCount > out.planeOf.size()) continue;
    const int ci = static_cast<int>(out.cylinders.size());
    CylindricalPatch c;
    const Eigen::Vector3d axis = f.direction.normalized();
    c.direction = axis;
    c.radius = f.radius;
    c.convex = f.convex;
    c.point = f.point + f.axialMin * axis;
    c.length = f.axialMax - f.axialMin;
    const Eigen::Vector3d e1 = perpendicular(axis), e2 = axis.cross(e1);
    std::vector<double> angles;
    double closest = f.radius;
    for (std::size_t t = f.firstTriangle; t < f.firstTriangle + f.triangleCount; ++t) {
      const int plane = out.planeOf[t];
      if (plane < 0) continue;
      c.triangles.push_back(static_cast<int>(t));
      c.facets.push_back(plane);
      for (int k = 0; k < 3; ++k) {
        Eigen::Vector3d d = wv[static_cast<std::size_t>(topo.welded.triangles[t][k])] - c.point;
        d -= axis * axis.dot(d);
        c.residual = std::max(c.residual, std::abs(d.norm() - f.radius));
        angles.push_back(std::atan2(d.dot(e2), d.dot(e1)));
      }
      // The facet's plane lies inside the true surface by up to the sagitta.
      Eigen::Vector3d centre = (vertexOf(topo.welded, static_cast<int>(t), 0) + vertexOf(topo.welded, static_cast<int>(t), 1) +
                                vertexOf(topo.welded, static_cast<int>(t), 2)) / 3.0 - c.point;
      centre -= axis * axis.dot(centre);
      closest = std::min(closest, std::abs(out.normals[t].dot(centre)));
    }
    if (c.triangles.empty()) continue;
    c.sagitta = std::max(0.0, f.radius - closest);
    std::sort(angles.begin(), angles.end());
    double gap = 2.0 * kPi - (angles.back() - angles.front());
    for (std::size_t i = 1; i < angles.size(); ++i) gap = std::max(gap, angles[i] - angles[i - 1]);
    c.coverage = std::clamp(2.0 * kPi - gap, 0.0, 2.0 * kPi);
    std::sort(c.facets.begin(), c.facets.end());
    c.facets.erase(std::unique(c.facets.begin(), c.facets.end()), c.facets.end());
    for (int t : c.triangles) out.cylinderOf[static_cast<std::size_t>(t)] = ci;
    for (int pl : c.facets)
      if (cylOfPlane[static_cast<std::size_t>(pl)] < 0) cylOfPlane[static_cast<std::size_t>(pl)] = ci;
    out.cylinders.push_back(std::move(c));
  }
}

// Which planar facets border which: for each, the edges it shares with another.
std::vector<std::vector<PatchEdge>> planeAdjacency(const Topology& topo, const SurfacePatches& out) {
  const std::size_t np = out.planes.size();
  std::vector<std::vector<PatchEdge>> adj(np);
  for (std::size_t t = 0; t < topo.neighbour.size(); ++t) {
    const int pt = out.planeOf[t];
    if (pt < 0) continue;
    const Eigen::Vector3i& w = topo.welded.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const int nb = topo.neighbour[t][k];
      if (nb < 0) continue;
      const int pn = out.planeOf[static_cast<std::size_t>(nb)];
      if (pn >= 0 && pn != pt) adj[static_cast<std::size_t>(pt)].push_back({pn, w[k], w[(k + 1) % 3]});
    }
  }
  return adj;
}

// Fits a cylinder about `axis` to a region of facets: the circle through its vertices seen along the axis,
// within the distance tolerance, every facet facing the same way from it (outward: convex). False when they
// do not lie on one.
bool fitCylinder(const Topology& topo, const SurfacePatches& out, const std::vector<int>& region, const Eigen::Vector3d& axis, CylindricalPatch& c) {
  const PatchOptions& o = out.options;
  const auto& wv = topo.welded.vertices;
  // Unique vertices of the region, projected onto the plane normal to the axis.
  const Eigen::Vector3d e1 = perpendicular(axis), e2 = axis.cross(e1);
  std::vector<int> verts;
  for (int f : region)
    for (int tri : out.planes[static_cast<std::size_t>(f)].triangles)
      for (int k = 0; k < 3; ++k) verts.push_back(topo.welded.triangles[static_cast<std::size_t>(tri)][k]);
  std::sort(verts.begin(), verts.end());
  verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
  std::vector<Eigen::Vector2d> pts;
  pts.reserve(verts.size());
  double tmin = 1e300, tmax = -1e300;
  for (int v : verts) {
    const Eigen::Vector3d& x = wv[static_cast<std::size_t>(v)];
    pts.emplace_back(x.dot(e1), x.dot(e2));
    tmin = std::min(tmin, x.dot(axis));
    tmax = std::max(tmax, x.dot(axis));
  }
  Eigen::Vector2d centre;
  double radius = 0.0;
  if (!fitCircle(pts, centre, radius)) return false;
  double residual = 0.0;
  for (const auto& pt : pts) residual = std::max(residual, std::abs((pt - centre).norm() - radius));
  c.residual = residual;
  if (residual > std::max(o.distanceTolerance, 1e-6 * radius)) return false;
  const Eigen::Vector3d c3 = centre.x() * e1 + centre.y() * e2;
  c.direction = axis;
  c.radius = radius;
  c.point = c3 + tmin * axis;
  c.length = tmax - tmin;
  int outward = 0, inward = 0;
  double closest = radius, coverage = 0.0;
  for (int f : region) {
    const PlanarPatch& p = out.planes[static_cast<std::size_t>(f)];
    Eigen::Vector3d radial = p.origin - c3;
    radial -= axis * axis.dot(radial);
    const double s = p.normal.dot(radial);
    (s > 0.0 ? outward : inward) += 1;
    closest = std::min(closest, std::abs(s));
    // Arc subtended by the facet's vertices.
    const double mid = std::atan2(radial.dot(e2), radial.dot(e1));
    double lo = 0.0, hi = 0.0;
    for (int tri : p.triangles)
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d d = wv[static_cast<std::size_t>(topo.welded.triangles[static_cast<std::size_t>(tri)][k])] - c3;
        double ang = std::atan2(d.dot(e2), d.dot(e1)) - mid;
        ang = std::remainder(ang, 2.0 * kPi);
        lo = std::min(lo, ang);
        hi = std::max(hi, ang);
      }
    coverage += hi - lo;
  }
  c.convex = inward == 0;
  c.sagitta = std::max(0.0, radius - closest);
  c.coverage = std::min(coverage, 2.0 * kPi);
  return outward == 0 || inward == 0;
}

// End faces (rims) of each cylinder. A face ends a cylinder when every point of it (outline corners and
// triangle centroids) lies on the material's side of the radius. A plate's face borders each of its
// hundreds of holes, so for a bore only the points that can lie within the radius are looked at: those
// whose coordinate along the face's u lies within radius / cos(tilt) of where the axis crosses the face,
// from the face's points sorted along u (built once per face, when a bore first asks).
void findRims(const Topology& topo, SurfacePatches& out, const std::vector<std::vector<PatchEdge>>& adj, const std::vector<int>& cylOfPlane) {
  const PatchOptions& o = out.options;
  const std::size_t np = out.planes.size();
  const double cosTol = std::cos(o.angleTolerance);
  const TriMesh& welded = topo.welded;
  std::vector<std::vector<std::pair<double, Eigen::Vector3d>>> alongU(np);
  const auto pointsAlongU = [&](std::size_t pi) -> const std::vector<std::pair<double, Eigen::Vector3d>>& {
    auto& pts = alongU[pi];
    if (!pts.empty()) return pts;
    const PlanarPatch& p = out.planes[pi];
    for (const Outline& loop : p.outline)
      for (const auto& q : loop) pts.emplace_back(q.x(), p.toMesh(q));
    for (int t : p.triangles) {
      const Eigen::Vector3d c = (vertexOf(welded, t, 0) + vertexOf(welded, t, 1) + vertexOf(welded, t, 2)) / 3.0;
      pts.emplace_back(p.u.dot(c - p.origin), c);
    }
    std::sort(pts.begin(), pts.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    return pts;
  };
  for (std::size_t ci = 0; ci < out.cylinders.size(); ++ci) {
    const CylindricalPatch& c = out.cylinders[ci];
    const double tol = std::max(o.distanceTolerance, 1e-6 * c.radius);
    std::vector<int> candidates;
    for (int f : c.facets)
      for (const PatchEdge& e : adj[static_cast<std::size_t>(f)])
        if (cylOfPlane[static_cast<std::size_t>(e.other)] < 0) candidates.push_back(e.other);
    std::sort(candidates.begin(), candidates.end());
    candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
    const auto inside = [&](const Eigen::Vector3d& x) {
      Eigen::Vector3d d = x - c.point;
      d -= c.direction * c.direction.dot(d);
      const double r = d.norm();
      return c.convex ? r <= c.radius + tol : r >= c.radius - tol;
    };
    for (int pi : candidates) {
      const PlanarPatch& p = out.planes[static_cast<std::size_t>(pi)];
      const double tilt = std::abs(p.normal.dot(c.direction));
      if (tilt < cosTol || p.outline.empty()) continue;
      const auto& pts = pointsAlongU(static_cast<std::size_t>(pi));
      auto from = pts.begin(), to = pts.end();
      if (!c.convex) {
        // Where the axis crosses the face, along u; a point farther along u than radius / tilt is
        // farther than the radius from the axis.
        const Eigen::Vector3d q = c.point + c.direction * ((p.offset() - p.normal.dot(c.point)) / p.normal.dot(c.direction));
        const double at = p.u.dot(q - p.origin), reach = c.radius / tilt + tol;
        from = std::lower_bound(pts.begin(), pts.end(), at - reach, [](const auto& e, double x) { return e.first < x; });
        to = std::upper_bound(from, pts.end(), at + reach, [](double x, const auto& e) { return x < e.first; });
      }
      if (std::all_of(from, to, [&](const auto& e) { return inside(e.second); })) out.planes[static_cast<std::size_t>(pi)].rimOf.push_back(static_cast<int>(ci));
    }
  }
}

void findCylinders(const Topology& topo, SurfacePatches& out, const CadSolid* cad) {
  const PatchOptions& o = out.options;
  const std::size_t np = out.planes.size();
  const std::vector<std::vector<PatchEdge>> adj = planeAdjacency(topo, out);
  const auto& wv = topo.welded.vertices;
  auto edgeDir = [&](const PatchEdge& e) {
    return (wv[static_cast<std::size_t>(e.b)] - wv[static_cast<std::size_t>(e.a)]).normalized().eval();
  };
  const double cosTol = std::cos(o.angleTolerance);
  const double sinTol = std::sin(o.angleTolerance);
  std::vector<int> cylOfPlane(np, -1);
  std::vector<char> tried(np, 0);
  std::vector<int> mark(np, -1);  // region membership by seed attempt

  int attempt = 0;
  if (cad) cylindersFromCad(*cad, topo, out, cylOfPlane);
  for (std::size_t seed = 0; seed < np && !cad; ++seed) {
    if (cylOfPlane[seed] >= 0 || tried[seed]) continue;
    const Eigen::Vector3d& n0 = out.planes[seed].normal;
    for (const PatchEdge& e0 : adj[seed]) {
      const auto q = static_cast<std::size_t>(e0.other);
      if (cylOfPlane[q] >= 0 || tried[q]) continue;
      const Eigen::Vector3d& n1 = out.planes[q].normal;
      const double turn = std::acos(std::clamp(n0.dot(n1), -1.0, 1.0));
      if (turn <= o.angleTolerance || turn > o.maxFacetTurn) continue;
      const Eigen::Vector3d axis = n0.cross(n1).normalized();
      if (std::abs(edgeDir(e0).dot(axis)) < cosTol) continue;
      // Grow the region of facets around this axis.
      ++attempt;
      std::vector<int> region{static_cast<int>(seed), static_cast<int>(q)};
      mark[seed] = attempt;
      mark[q] = attempt;
      std::deque<int> queue(region.begin(), region.end());
      while (!queue.empty()) {
        const auto x = static_cast<std::size_t>(queue.front());
        queue.pop_front();
        for (const PatchEdge& e : adj[x]) {
          const auto y = static_cast<std::size_t>(e.other);
          if (mark[y] == attempt || cylOfPlane[y] >= 0) continue;
          const Eigen::Vector3d& ny = out.planes[y].normal;
          if (std::abs(ny.dot(axis)) > sinTol) continue;
          if (std::abs(edgeDir(e).dot(axis)) < cosTol) continue;
          if (std::acos(std::clamp(out.planes[x].normal.dot(ny), -1.0, 1.0)) > o.maxFacetTurn) continue;
          mark[y] = attempt;
          region.push_back(static_cast<int>(y));
          queue.push_back(static_cast<int>(y));
        }
      }
      CylindricalPatch c;
      const bool ok = static_cast<int>(region.size()) >= o.minFacets && fitCylinder(topo, out, region, axis, c);
      if (ok) {
        const int ci = static_cast<int>(out.cylinders.size());
        std::sort(region.begin(), region.end());
        c.facets = region;
        for (int f : region) {
          cylOfPlane[static_cast<std::size_t>(f)] = ci;
          for (int tri : out.planes[static_cast<std::size_t>(f)].triangles) {
            c.triangles.push_back(tri);
            out.cylinderOf[static_cast<std::size_t>(tri)] = ci;
          }
        }
        std::sort(c.triangles.begin(), c.triangles.end());
        out.cylinders.push_back(std::move(c));
        break;
      }
      // A ruled surface that is not a cylinder (an involute flank, say): do not try its facets again.
      for (int f : region) tried[static_cast<std::size_t>(f)] = 1;
      break;
    }
  }
  findRims(topo, out, adj, cylOfPlane);
}

}  // namespace

SurfacePatches classifySurfaces(const TriMesh& mesh, const PatchOptions& options) { return classifySurfaces(mesh, nullptr, options); }

SurfacePatches classifySurfaces(const TriMesh& mesh, const CadSolid* cad, const PatchOptions& options) {
  SurfacePatches out;
  out.options = options;
  const std::size_t n = mesh.triangles.size();
  out.planeOf.assign(n, -1);
  out.cylinderOf.assign(n, -1);
  if (n == 0) return out;
  const Topology topo = buildTopology(mesh, options, out);

  // Planar patches by region growing against the seed triangle's plane (no drift on curved surfaces).
  const double cosTol = std::cos(options.angleTolerance);
  std::deque<int> queue;
  for (std::size_t seed = 0; seed < n; ++seed) {
    if (!topo.valid[seed] || out.planeOf[seed] >= 0) continue;
    const int index = static_cast<int>(out.planes.size());
    PlanarPatch p;
    const Eigen::Vector3d n0 = out.normals[seed];
    const Eigen::Vector3d x0 = vertexOf(mesh, static_cast<int>(seed), 0);
    out.planeOf[seed] = index;
    p.triangles.push_back(static_cast<int>(seed));
    queue.push_back(static_cast<int>(seed));
    while (!queue.empty()) {
      const auto t = static_cast<std::size_t>(queue.front());
      queue.pop_front();
      for (int k = 0; k < 3; ++k) {
        const int nb = topo.neighbour[t][k];
        if (nb < 0 || out.planeOf[static_cast<std::size_t>(nb)] >= 0) continue;
        if (out.normals[static_cast<std::size_t>(nb)].dot(n0) < cosTol) continue;
        bool onPlane = true;
        for (int j = 0; j < 3 && onPlane; ++j)
          onPlane = std::abs(n0.dot(vertexOf(mesh, nb, j) - x0)) <= options.distanceTolerance;
        if (!onPlane) continue;
        out.planeOf[static_cast<std::size_t>(nb)] = index;
        p.triangles.push_back(nb);
        queue.push_back(nb);
      }
    }
    std::sort(p.triangles.begin(), p.triangles.end());
    fitPlane(p, mesh, out);
    out.planes.push_back(std::move(p));
  }
  out.outlineEdges.assign(n, 0);
  for (std::size_t t = 0; t < n; ++t) {
    if (out.planeOf[t] < 0) continue;
    for (int k = 0; k < 3; ++k) {
      const int nb = topo.neighbour[t][k];
      if (nb < 0 || out.planeOf[static_cast<std::size_t>(nb)] != out.planeOf[t])
        out.outlineEdges[t] = static_cast<unsigned char>(out.outlineEdges[t] | (1u << k));
    }
  }
  const double mergeDistance = 0.01 * options.distanceTolerance;
  for (std::size_t i = 0; i < out.planes.size(); ++i) {
    PlanarPatch& p = out.planes[i];
    p.outline = outlineOf(p, static_cast<int>(i), topo, out.planeOf, mergeDistance);
    std::vector<Eigen::Vector2d> all;
    for (const auto& loop : p.outline) all.insert(all.end(), loop.begin(), loop.end());
    p.hull = geom2::convexHull(std::move(all));
  }
  // The solid's own faces when the mesh is its tessellation (same triangles, same order).
  if (cad && cad->mesh.triangles.size() != n) cad = nullptr;
  findCylinders(topo, out, cad);
  if (cad) {
    out.curved.assign(n, 0);
    for (const CadFace& f : cad->faces)
      if (f.surface == CadFace::Surface::Other || f.surface == CadFace::Surface::Cone)
        for (std::size_t t = f.firstTriangle; t < f.firstTriangle + f.triangleCount && t < n; ++t) out.curved[t] = 1;
  }
  std::vector<char> facet(out.planes.size(), 0);
  for (const CylindricalPatch& c : out.cylinders)
    for (const int f : c.facets) facet[static_cast<std::size_t>(f)] = 1;
  for (std::size_t i = 0; i < out.planes.size(); ++i)
    if (!facet[i]) out.largestPlanes.push_back(static_cast<int>(i));
  const auto larger = [&](int x, int y) { return out.planes[static_cast<std::size_t>(x)].area > out.planes[static_cast<std::size_t>(y)].area; };
  const std::size_t keep = std::min(out.largestPlanes.size(), SurfacePatches::kLargestPlanes);
  std::partial_sort(out.largestPlanes.begin(), out.largestPlanes.begin() + static_cast<std::ptrdiff_t>(keep), out.largestPlanes.end(), larger);
  out.largestPlanes.resize(keep);
  return out;
}

}  // namespace vaw::collision
