#include "vaw/collision/collision_world.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <sstream>
#include <tuple>
#include <utility>

#include "fcl_includes.hpp"
#include "geometry2d.hpp"
#include "pair_geometry.hpp"

namespace vaw::collision {

std::string_view name(FilterMode m) {
  switch (m) {
    case FilterMode::NoCare: return "NOCARE";
    case FilterMode::KeepCoplanar: return "KEEP_COPLANAR";
    case FilterMode::SkipCoplanar: return "SKIP_COPLANAR";
    case FilterMode::SkipCoaxial: return "SKIP_COAXIAL";
  }
  return "?";
}

std::string_view name(ProxyKind k) {
  switch (k) {
    case ProxyKind::Mesh: return "mesh";
    case ProxyKind::SimplifiedMesh: return "simplified mesh";
    case ProxyKind::Box: return "box";
    case ProxyKind::Sphere: return "sphere";
    case ProxyKind::Cylinder: return "cylinder";
    case ProxyKind::None: return "none";
  }
  return "?";
}

namespace {

using BV = fcl::OBBRSSd;
using Model = fcl::BVHModel<BV>;
using BaseNode = fcl::detail::MeshCollisionTraversalNodeOBBRSS<double>;
using pairgeom::Tri;

std::string fmt(double v) {
  std::ostringstream s;
  s.precision(4);
  s << v;
  return s.str();
}

}  // namespace

struct WorldObject {
  ObjectId id;
  ObjectInfo info;
  std::shared_ptr<const TriMesh> mesh;      // collision mesh (null for a primitive)
  std::shared_ptr<Model> bvh;               // null for a primitive
  std::shared_ptr<fcl::CollisionGeometryd> geometry;
  std::unique_ptr<fcl::CollisionObjectd> object;
  std::vector<int> bvhToMesh;               // BVH primitive -> mesh triangle
  std::shared_ptr<const SurfacePatches> patches = std::make_shared<const SurfacePatches>();
  // Per BVH node: the one planar / cylindrical patch all its triangles belong to, else -1. A node pair of
  // two coplanar faces (or two coaxial equal cylinders) is skipped whole under SKIP_COPLANAR (SKIP_COAXIAL).
  std::vector<int> nodePlane, nodeCylinder;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d geometryOffset = Eigen::Isometry3d::Identity();  // object frame -> FCL geometry frame
  Eigen::AlignedBox3d localBounds;
  Eigen::Vector3d boxHalf = Eigen::Vector3d::Zero();  // Box proxies
  Eigen::Vector3d com = Eigen::Vector3d::Zero();

  [[nodiscard]] Eigen::Isometry3d fclPose(const Eigen::Isometry3d& p) const { return p * geometryOffset; }
  [[nodiscard]] double sagitta(int tri) const {
    const int c = patches->cylinderOf.empty() ? -1 : patches->cylinderOf[static_cast<std::size_t>(tri)];
    return c < 0 ? 0.0 : patches->cylinders[static_cast<std::size_t>(c)].sagitta;
  }
};

// What the blocked check may skip for one support (see CollisionWorld::prepare).
struct SupportCache {
  // Plane: base BVH nodes whose triangles all lie at or below the base plane (+ a quarter tolerance). A part
  // that lies entirely on its own side of its contact plane and rests on the base plane cannot reach them.
  std::vector<char> baseBelow;
  bool planeCull = false;
  double partReach = 0.0;  // m, farthest point of the part from its plane / axis point (bounds a tilt's effect)
  // Axis: base BVH nodes whose triangles all lie within the fit's radius of the base axis (+ a quarter
  // tolerance): the shaft, its chamfer and cap. A part that lies entirely outside that radius around its own
  // axis (a sleeve, a gear on its bore) and sits on the axis can only touch them along the fit, which
  // SKIP_COAXIAL ignores anyway.
  std::vector<char> baseInside;
  bool axisCull = false;
  double partNearest = 0.0;  // m, nearest point of the part to its own axis (its bore's radius)
  double fitRadius = 0.0;    // m, of the base's cylinders in the fit

  // What CollisionWorld::freeMotion reads, found once from the geometry (docs/collision.md, "Free motion").
  struct Span {
    double lo, hi;
  };
  bool free = false;
  // Axis: the part's radial band about its own axis (nearest triangle, farthest vertex) and its extent
  // along it from its axis point; the axial spans, from the base's axis point, of the base's faces that
  // come within that band widened by the fit's clearance (merged); each fit pair's axial spans (part, base).
  double bandMin = 0.0, bandMax = 0.0;
  Span partSpan{0.0, 0.0};
  std::vector<Span> axialObstacles;
  std::vector<std::pair<Span, Span>> fitSpans;
  // Plane: the part's height over its contact plane; the base plane's 2-D coordinates; the 2-D boxes of the
  // base's faces that rise into that height; the support face's outline; its convex hull when the base's
  // face is one convex loop (and whether the part's face is convex too).
  double partHeight = 0.0;
  Eigen::Vector3d e1 = Eigen::Vector3d::UnitX(), e2 = Eigen::Vector3d::UnitY();
  std::vector<geom2::Box> planeObstacles;
  std::vector<geom2::Segment> baseOutline;
  std::vector<Eigen::Vector2d> convexBase;
  bool partFaceConvex = false;
};

struct CollisionWorld::Impl {
  Tolerances tol;
  Diagnostics diagnostics;
  std::optional<PartId> base;
  std::vector<WorldObject> parts;
  std::vector<WorldObject> environment;
  std::unique_ptr<fcl::DynamicAABBTreeCollisionManagerd> manager;

  // One FCL object per object with geometry, at its pose, in a fresh broad phase.
  void makeBroadPhase();
  WorldObject& get(ObjectId id) {
    auto& v = id.kind == ObjectId::Kind::Part ? parts : environment;
    if (id.index >= v.size()) throw std::out_of_range("collision: no such object");
    return v[id.index];
  }
  const WorldObject& get(ObjectId id) const { return const_cast<Impl*>(this)->get(id); }
};

namespace {

// ---------------------------------------------------------------------------------------------------
// Building
// ---------------------------------------------------------------------------------------------------

void warn(Diagnostics& d, Diagnostic::Severity sev, const std::string& object, const std::string& field,
          const std::string& expected, const std::string& found) {
  d.push_back({sev, object, "collision." + field, expected, found});
}

std::string displayName(const WorldObject& o) {
  return (o.id.kind == ObjectId::Kind::Part ? "part \"" : "environment object \"") + o.info.name + "\"";
}

// Builds the BVH of a mesh (valid triangles only) and its surface patches; reports what is wrong with it.
void buildMesh(WorldObject& o, std::shared_ptr<const TriMesh> mesh, const PatchOptions& popts, Diagnostics& diags) {
  const auto t0 = std::chrono::steady_clock::now();
  o.mesh = std::move(mesh);
  const TriMesh& m = *o.mesh;
  o.patches = std::make_shared<const SurfacePatches>(classifySurfaces(m, popts));
  const std::string who = displayName(o);
  if (o.patches->degenerateTriangles > 0)
    warn(diags, Diagnostic::Severity::Warning, who, "degenerate-triangles",
         "triangles with three distinct, finite corners and non-zero area",
         std::to_string(o.patches->degenerateTriangles) + " degenerate or invalid triangles (left out of collision)");
  if (o.patches->boundaryEdges > 0)
    warn(diags, Diagnostic::Severity::Warning, who, "open-mesh", "a closed mesh (every edge shared by two triangles)",
         std::to_string(o.patches->boundaryEdges) + " open edges: collision is tested on the surface only");
  if (o.patches->nonManifoldEdges > 0)
    warn(diags, Diagnostic::Severity::Warning, who, "non-manifold", "edges shared by at most two triangles",
         std::to_string(o.patches->nonManifoldEdges) + " non-manifold edges: surface patches end there");
  if (o.patches->duplicateVertices > 0)
    warn(diags, Diagnostic::Severity::Warning, who, "duplicate-vertices", "one vertex per position",
         std::to_string(o.patches->duplicateVertices) + " duplicated vertices: merged for finding neighbours");

  std::vector<fcl::Vector3d> verts(m.vertices.size());
  for (std::size_t i = 0; i < m.vertices.size(); ++i) verts[i] = m.vertices[i].allFinite() ? m.vertices[i] : Eigen::Vector3d::Zero();
  std::vector<fcl::Triangle> tris;
  tris.reserve(m.triangles.size());
  o.bvhToMesh.clear();
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    if (o.patches->planeOf[t] < 0) continue;
    const Eigen::Vector3i& tr = m.triangles[t];
    tris.emplace_back(static_cast<std::size_t>(tr[0]), static_cast<std::size_t>(tr[1]), static_cast<std::size_t>(tr[2]));
    o.bvhToMesh.push_back(static_cast<int>(t));
  }
  if (tris.empty()) {
    warn(diags, Diagnostic::Severity::Error, who, "no-geometry", "at least one valid triangle",
         std::to_string(m.triangles.size()) + " triangles, none valid: the object takes no part in collision");
    o.info.proxy = ProxyKind::None;
    o.info.proxyReason = "no valid triangle";
    return;
  }
  auto bvh = std::make_shared<Model>();
  bool ok = bvh->beginModel(static_cast<int>(tris.size()), static_cast<int>(verts.size())) == fcl::BVH_OK;
  ok = ok && bvh->addSubModel(verts, tris) == fcl::BVH_OK;
  ok = ok && bvh->endModel() == fcl::BVH_OK;
  if (!ok) {
    warn(diags, Diagnostic::Severity::Error, who, "bvh", "a mesh FCL can build a hierarchy for", "FCL refused the mesh");
    o.info.proxy = ProxyKind::None;
    o.info.proxyReason = "FCL refused the mesh";
    return;
  }
  bvh->computeLocalAABB();
  o.bvh = bvh;
  // Single-patch ids per node (children come after their parent in FCL's node array).
  const int nodes = bvh->getNumBVs();
  o.nodePlane.assign(static_cast<std::size_t>(nodes), -1);
  o.nodeCylinder.assign(static_cast<std::size_t>(nodes), -1);
  for (int i = nodes - 1; i >= 0; --i) {
    const auto& node = bvh->getBV(i);
    const auto k = static_cast<std::size_t>(i);
    if (node.isLeaf()) {
      const auto tri = static_cast<std::size_t>(o.bvhToMesh[static_cast<std::size_t>(node.primitiveId())]);
      o.nodePlane[k] = o.patches->planeOf[tri];
      o.nodeCylinder[k] = o.patches->cylinderOf[tri];
    } else {
      const auto c0 = static_cast<std::size_t>(node.first_child), c1 = c0 + 1;
      o.nodePlane[k] = o.nodePlane[c0] == o.nodePlane[c1] ? o.nodePlane[c0] : -1;
      o.nodeCylinder[k] = o.nodeCylinder[c0] == o.nodeCylinder[c1] ? o.nodeCylinder[c0] : -1;
    }
  }
  o.geometry = bvh;
  o.info.triangles = tris.size();
  o.info.planarPatches = o.patches->planes.size();
  o.info.cylindricalPatches = o.patches->cylinders.size();
  o.localBounds = Eigen::AlignedBox3d();
  for (const fcl::Triangle& t : tris)
    for (int k = 0; k < 3; ++k) o.localBounds.extend(m.vertices[t[k]]);
  o.info.buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Signed distance from a point (primitive frame) to a box / sphere / z-cylinder centred there.
double sdfBox(const Eigen::Vector3d& x, const Eigen::Vector3d& h) {
  const Eigen::Vector3d q = x.cwiseAbs() - h;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}
double sdfCylinder(const Eigen::Vector3d& x, double r, double halfH) {
  const Eigen::Vector2d d(std::hypot(x.x(), x.y()) - r, std::abs(x.z()) - halfH);
  return d.cwiseMax(0.0).norm() + std::min(d.maxCoeff(), 0.0);
}

// Tries the exact primitive an environment object was made from; returns false to keep its mesh.
bool tryPrimitive(WorldObject& o, const EnvironmentObject& e, Diagnostics& diags) {
  const std::string& src = e.shapeSource;
  ProxyKind kind;
  if (src == "primitive box") kind = ProxyKind::Box;
  else if (src == "primitive sphere") kind = ProxyKind::Sphere;
  else if (src == "primitive cylinder") kind = ProxyKind::Cylinder;
  else return false;
  const TriMesh& m = *e.mesh;
  if (m.vertices.empty()) return false;
  const auto t0 = std::chrono::steady_clock::now();
  Eigen::AlignedBox3d b;
  for (const auto& v : m.vertices) b.extend(v);
  const Eigen::Vector3d c = b.center(), size = b.sizes();
  std::function<double(const Eigen::Vector3d&)> sdf;
  if (kind == ProxyKind::Box) {
    o.boxHalf = size / 2.0;
    o.geometry = std::make_shared<fcl::Boxd>(size);
    sdf = [h = o.boxHalf](const Eigen::Vector3d& x) { return sdfBox(x, h); };
  } else if (kind == ProxyKind::Sphere) {
    const double r = size.maxCoeff() / 2.0;
    o.geometry = std::make_shared<fcl::Sphered>(r);
    sdf = [r](const Eigen::Vector3d& x) { return x.norm() - r; };
  } else {
    const double r = std::max(size.x(), size.y()) / 2.0;
    o.geometry = std::make_shared<fcl::Cylinderd>(r, size.z());
    sdf = [r, hz = size.z() / 2.0](const Eigen::Vector3d& x) { return sdfCylinder(x, r, hz); };
  }
  // Measured deviation: vertices and triangle centroids of the display mesh against the exact shape.
  double dev = 0.0;
  for (const auto& v : m.vertices) dev = std::max(dev, std::abs(sdf(v - c)));
  for (const auto& t : m.triangles) {
    bool ok = true;
    for (int k = 0; k < 3; ++k) ok = ok && t[k] >= 0 && static_cast<std::size_t>(t[k]) < m.vertices.size();
    if (!ok) continue;
    const Eigen::Vector3d& p0 = m.vertices[static_cast<std::size_t>(t[0])];
    const Eigen::Vector3d& p1 = m.vertices[static_cast<std::size_t>(t[1])];
    const Eigen::Vector3d& p2 = m.vertices[static_cast<std::size_t>(t[2])];
    for (const Eigen::Vector3d& g : {Eigen::Vector3d((p0 + p1 + p2) / 3.0), Eigen::Vector3d((p0 + p1) / 2.0),
                                     Eigen::Vector3d((p1 + p2) / 2.0), Eigen::Vector3d((p2 + p0) / 2.0)})
      dev = std::max(dev, std::abs(sdf(g - c)));
  }
  const double limit = 0.02 * size.minCoeff();
  if (!(dev <= limit)) {
    warn(diags, Diagnostic::Severity::Warning, displayName(o), "proxy-rejected",
         "a " + std::string(name(kind)) + " within " + fmt(limit) + " m of the mesh",
         "deviation " + fmt(dev) + " m: the mesh is used instead");
    o.geometry.reset();
    return false;
  }
  o.geometryOffset = Eigen::Isometry3d(Eigen::Translation3d(c));
  o.localBounds = b;
  o.info.proxy = kind;
  o.info.deviation = dev;
  o.info.triangles = 0;
  o.info.proxyReason = "exact " + std::string(name(kind)) + " from the scene's primitive (display mesh within " + fmt(dev) + " m)";
  o.info.buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return true;
}

// Largest distance from sampled points of `from` to the surface of `to` (FCL distance to a point).
double sampledDeviation(const TriMesh& from, const Model& to, std::size_t maxSamples) {
  std::vector<Eigen::Vector3d> samples;
  for (const auto& v : from.vertices)
    if (v.allFinite()) samples.push_back(v);
  for (const auto& t : from.triangles) {
    bool ok = true;
    for (int k = 0; k < 3; ++k) ok = ok && t[k] >= 0 && static_cast<std::size_t>(t[k]) < from.vertices.size();
    if (!ok) continue;
    const Eigen::Vector3d& p0 = from.vertices[static_cast<std::size_t>(t[0])];
    const Eigen::Vector3d& p1 = from.vertices[static_cast<std::size_t>(t[1])];
    const Eigen::Vector3d& p2 = from.vertices[static_cast<std::size_t>(t[2])];
    samples.push_back((p0 + p1 + p2) / 3.0);
    samples.push_back((p0 + p1) / 2.0);
  }
  const std::size_t stride = std::max<std::size_t>(1, samples.size() / std::max<std::size_t>(1, maxSamples));
  auto point = std::make_shared<fcl::Sphered>(0.0);
  double dev = 0.0;
  fcl::DistanceRequestd req;
  for (std::size_t i = 0; i < samples.size(); i += stride) {
    fcl::DistanceResultd res;
    fcl::Transform3d tf = fcl::Transform3d::Identity();
    tf.translation() = samples[i];
    fcl::distance(&to, fcl::Transform3d::Identity(), point.get(), tf, req, res);
    dev = std::max(dev, std::max(0.0, res.min_distance));
  }
  return dev;
}

// FNV-1a over the vertices' and triangles' bytes, eight at a time (a hash hit is confirmed by comparing).
std::uint64_t meshHash(const TriMesh& m) {
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&](const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    std::size_t i = 0;
    for (; i + 8 <= bytes; i += 8) {
      std::uint64_t w;
      std::memcpy(&w, p + i, 8);
      h = (h ^ w) * 1099511628211ull;
    }
    for (; i < bytes; ++i) h = (h ^ p[i]) * 1099511628211ull;
  };
  if (!m.vertices.empty()) mix(m.vertices.data(), m.vertices.size() * sizeof(Eigen::Vector3d));
  if (!m.triangles.empty()) mix(m.triangles.data(), m.triangles.size() * sizeof(Eigen::Vector3i));
  return h;
}

Eigen::AlignedBox3d transformedBox(const Eigen::AlignedBox3d& b, const Eigen::Isometry3d& tf) {
  Eigen::AlignedBox3d out;
  if (b.isEmpty()) return out;
  for (int i = 0; i < 8; ++i) out.extend(tf * b.corner(static_cast<Eigen::AlignedBox3d::CornerType>(i)));
  return out;
}

// ---------------------------------------------------------------------------------------------------
// Mesh-mesh traversal with the filter in the leaf test
// ---------------------------------------------------------------------------------------------------

struct PairContext {
  const WorldObject* A = nullptr;
  const WorldObject* B = nullptr;
  FilterMode mode = FilterMode::NoCare;
  QueryOptions opt;
  Tolerances tol;
  Eigen::Isometry3d tfA = Eigen::Isometry3d::Identity();  // A's FCL frame -> world
  QueryResult* out = nullptr;
  double cosAngle = 1.0;
  std::vector<signed char> coaxCache;  // per (cylinder of A, cylinder of B): -1 unknown, 0 no, 1 yes
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // B frame -> A frame
  Eigen::Vector3d T = Eigen::Vector3d::Zero();
  bool stop = false;
  // Node culling for a support's blocked check (A = the part, B = the base); null when not in force.
  const std::vector<char>* bBelow = nullptr;
  // A support's fit with clearance (A = the part, B = the base): these bore-and-shaft pairs are coaxial
  // with their axes up to `fitClearance` apart (the part rests in its play) and radii that differ.
  const std::vector<std::pair<int, int>>* fit = nullptr;
  double fitClearance = 0.0;

  // Every triangle pair of node b1 (of A) and node b2 (of B) would be dropped by the mode.
  bool skipsWhole(int b1, int b2) {
    if (mode == FilterMode::SkipCoplanar || (opt.dropTouching && mode != FilterMode::KeepCoplanar)) {
      const int pa = A->nodePlane[static_cast<std::size_t>(b1)], pb = B->nodePlane[static_cast<std::size_t>(b2)];
      if (pa >= 0 && pb >= 0 && planesCoincide(pa, pb)) return true;
    }
    if (mode == FilterMode::SkipCoaxial) {
      const int ca = A->nodeCylinder[static_cast<std::size_t>(b1)], cb = B->nodeCylinder[static_cast<std::size_t>(b2)];
      if (ca >= 0 && cb >= 0 && cylindersCoaxial(ca, cb)) return true;
      if (rimAgainstCylinder(A->nodePlane[static_cast<std::size_t>(b1)], cb, ca, B->nodePlane[static_cast<std::size_t>(b2)])) return true;
    }
    return false;
  }

  // An end face of one cylinder (planar patch pa of A, or pb of B) against the other's equal, coaxial
  // cylinder of the opposite kind (a sleeve's end face on its shaft, a shaft's cap in its bore).
  bool rimAgainstCylinder(int pa, int cb, int ca, int pb) {
    if (pa >= 0 && cb >= 0)
      for (int rim : A->patches->planes[static_cast<std::size_t>(pa)].rimOf)
        if (A->patches->cylinders[static_cast<std::size_t>(rim)].convex != B->patches->cylinders[static_cast<std::size_t>(cb)].convex &&
            cylindersCoaxial(rim, cb))
          return true;
    if (ca >= 0 && pb >= 0)
      for (int rim : B->patches->planes[static_cast<std::size_t>(pb)].rimOf)
        if (A->patches->cylinders[static_cast<std::size_t>(ca)].convex != B->patches->cylinders[static_cast<std::size_t>(rim)].convex &&
            cylindersCoaxial(ca, rim))
          return true;
    return false;
  }

  // Two planar patches' planes are parallel and within the distance tolerance (less both fits' residuals),
  // so every pair of their triangles is coplanar.
  bool planesCoincide(int pa, int pb) const {
    const PlanarPatch& a = A->patches->planes[static_cast<std::size_t>(pa)];
    const PlanarPatch& b = B->patches->planes[static_cast<std::size_t>(pb)];
    const Eigen::Vector3d nb = R * b.normal;
    if (std::abs(a.normal.dot(nb)) < cosAngle) return false;
    const double room = tol.distance - a.residual - b.residual;
    return std::abs(a.normal.dot(R * b.origin + T - a.origin)) <= room && std::abs(nb.dot(a.origin - (R * b.origin + T))) <= room;
  }

  bool coaxial(int ta, int tb) {
    const int ca = A->patches->cylinderOf[static_cast<std::size_t>(ta)];
    const int cb = B->patches->cylinderOf[static_cast<std::size_t>(tb)];
    if (ca >= 0 && cb >= 0) return cylindersCoaxial(ca, cb);
    return rimAgainstCylinder(A->patches->planeOf[static_cast<std::size_t>(ta)], cb, ca, B->patches->planeOf[static_cast<std::size_t>(tb)]);
  }

  bool cylindersCoaxial(int ca, int cb) {
    const std::size_t key = static_cast<std::size_t>(ca) * B->patches->cylinders.size() + static_cast<std::size_t>(cb);
    if (coaxCache[key] >= 0) return coaxCache[key] == 1;
    const CylindricalPatch& a = A->patches->cylinders[static_cast<std::size_t>(ca)];
    const CylindricalPatch& b = B->patches->cylinders[static_cast<std::size_t>(cb)];
    const Eigen::Vector3d db = R * b.direction;
    const Eigen::Vector3d pb = R * b.point + T;
    Eigen::Vector3d off = pb - a.point;
    off -= a.direction * a.direction.dot(off);
    const bool inFit = fit && std::find(fit->begin(), fit->end(), std::pair{ca, cb}) != fit->end();
    const double play = inFit ? fitClearance : 0.0;
    const bool yes = std::abs(a.direction.dot(db)) >= cosAngle && off.norm() <= tol.distance + tol.radius + play &&
                     (inFit || std::abs(a.radius - b.radius) <= tol.radius);
    coaxCache[key] = yes ? 1 : 0;
    return yes;
  }

  void record(int primA, int primB, const Tri& p, const Tri& q, bool keepCoplanarMode) {
    const int ta = A->bvhToMesh[static_cast<std::size_t>(primA)];
    const int tb = B->bvhToMesh[static_cast<std::size_t>(primB)];
    const Eigen::Vector3d na = A->patches->normals[static_cast<std::size_t>(ta)];
    const Eigen::Vector3d nb = R * B->patches->normals[static_cast<std::size_t>(tb)];
    Contact c;
    c.a = A->id;
    c.b = B->id;
    c.triangleA = ta;
    c.triangleB = tb;
    c.coplanar = pairgeom::coplanar(p, na, q, nb, cosAngle, tol.distance);
    c.allowance = tol.distance + A->sagitta(ta) + B->sagitta(tb);
    if (keepCoplanarMode) {
      if (!c.coplanar) return;
      c.coaxial = coaxial(ta, tb);
      c.position = tfA * ((p[0] + p[1] + p[2] + q[0] + q[1] + q[2]) / 6.0);
      c.penetration = 0.0;
    } else {
      if (!fcl::detail::Intersect<double>::intersect_Triangle(p[0], p[1], p[2], q[0], q[1], q[2])) return;
      ++out->intersecting;
      c.coaxial = coaxial(ta, tb);
      const bool skip = (mode == FilterMode::SkipCoplanar && c.coplanar) || (mode == FilterMode::SkipCoaxial && c.coaxial);
      pairgeom::Crossing x;
      if (!c.coplanar)
        x = pairgeom::crossing(p, na, A->patches->outlineEdges[static_cast<std::size_t>(ta)], q, nb,
                               B->patches->outlineEdges[static_cast<std::size_t>(tb)]);
      c.penetration = x.penetration;
      // A cylinder's facets lie up to its sagitta inside the true surface, along their own normal: that
      // much of a depth measured along that normal may be tessellation, not contact.
      const double along = std::abs(na.dot(nb));
      const double sa = A->sagitta(ta), sb = B->sagitta(tb);
      c.allowance = tol.distance + (x.aBinding ? sa * along + sb : sa + sb * along);
      if (skip || (opt.dropTouching && c.penetration <= c.allowance)) {
        ++out->filtered;
        return;
      }
      c.position = tfA * (x.crosses ? x.point : Eigen::Vector3d((p[0] + p[1] + p[2]) / 3.0));
    }
    out->contacts.push_back(c);
    if (out->contacts.size() >= opt.maxContacts) {
      out->truncated = !opt.stopAtFirst;
      stop = true;
    }
    if (opt.stopAtFirst) stop = true;
  }
};

class FilteredNode : public BaseNode {
 public:
  PairContext* ctx = nullptr;
  bool keepCoplanar = false;

  void leafTesting(int b1, int b2) const override {
    ++ctx->out->leafTests;
    const int i1 = this->model1->getBV(b1).primitiveId();
    const int i2 = this->model2->getBV(b2).primitiveId();
    const fcl::Triangle& t1 = this->tri_indices1[i1];
    const fcl::Triangle& t2 = this->tri_indices2[i2];
    const Tri p{this->vertices1[t1[0]], this->vertices1[t1[1]], this->vertices1[t1[2]]};
    const Tri q{ctx->R * this->vertices2[t2[0]] + ctx->T, ctx->R * this->vertices2[t2[1]] + ctx->T,
                ctx->R * this->vertices2[t2[2]] + ctx->T};
    ctx->record(i1, i2, p, q, keepCoplanar);
  }
  bool canStop() const override { return ctx->stop; }
  // KEEP_COPLANAR: bounding volumes within the distance tolerance count as overlapping (an inflated test).
  bool BVTesting(int b1, int b2) const override {
    ++ctx->out->boundingVolumeTests;
    if (ctx->bBelow && (*ctx->bBelow)[static_cast<std::size_t>(b2)]) return true;
    if (ctx->skipsWhole(b1, b2)) return true;
    if (!keepCoplanar) return BaseNode::BVTesting(b1, b2);
    return fcl::distance(this->R, this->T, this->model1->getBV(b1).bv, this->model2->getBV(b2).bv) > ctx->tol.distance;
  }
};

void meshMeshQuery(PairContext& ctx, const Eigen::Isometry3d& poseA, const Eigen::Isometry3d& poseB) {
  FilteredNode node;
  fcl::CollisionRequestd req;
  fcl::CollisionResultd res;
  const fcl::Transform3d tf1 = ctx.A->fclPose(poseA), tf2 = ctx.B->fclPose(poseB);
  const Model& m1 = *ctx.A->bvh;
  const Model& m2 = *ctx.B->bvh;
  if (!fcl::detail::initialize(static_cast<BaseNode&>(node), m1, tf1, m2, tf2, req, res)) return;
  ctx.tfA = tf1;
  ctx.R = node.R;
  ctx.T = node.T;
  ctx.cosAngle = std::cos(ctx.tol.angle);
  ctx.coaxCache.assign(ctx.A->patches->cylinders.size() * ctx.B->patches->cylinders.size(), -1);
  node.ctx = &ctx;
  node.keepCoplanar = ctx.mode == FilterMode::KeepCoplanar;
  fcl::detail::collide(&node, nullptr);
}

// A mesh triangle (in the box's frame) parallel to a box face and within `distance` of it.
bool coplanarWithBox(const Tri& t, const Eigen::Vector3d& n, const Eigen::Vector3d& half, double cosAngle, double distance) {
  for (int axis = 0; axis < 3; ++axis) {
    if (std::abs(n[axis]) < cosAngle) continue;
    for (double side : {-1.0, 1.0}) {
      bool near = true;
      for (const auto& x : t) near = near && std::abs(x[axis] - side * half[axis]) <= distance;
      if (near) return true;
    }
  }
  return false;
}

// Anything involving a primitive: FCL's own narrow phase; the coplanar test only against a box's faces.
void primitiveQuery(const WorldObject& A, const Eigen::Isometry3d& poseA, const WorldObject& B, const Eigen::Isometry3d& poseB,
                    FilterMode mode, const QueryOptions& opt, const Tolerances& tol, QueryResult& out) {
  const bool keep = mode == FilterMode::KeepCoplanar;
  std::shared_ptr<fcl::CollisionGeometryd> gA = A.geometry, gB = B.geometry;
  // KEEP_COPLANAR counts a gap up to the tolerance: test against the box grown by it.
  if (keep && A.info.proxy == ProxyKind::Box) gA = std::make_shared<fcl::Boxd>(Eigen::Vector3d(2.0 * (A.boxHalf.array() + tol.distance)));
  if (keep && B.info.proxy == ProxyKind::Box) gB = std::make_shared<fcl::Boxd>(Eigen::Vector3d(2.0 * (B.boxHalf.array() + tol.distance)));
  fcl::CollisionRequestd req(std::max<std::size_t>(opt.maxContacts * 4, 64), true);
  fcl::CollisionResultd res;
  fcl::collide(gA.get(), A.fclPose(poseA), gB.get(), B.fclPose(poseB), req, res);
  const double cosAngle = std::cos(tol.angle);
  std::vector<fcl::Contactd> contacts;
  res.getContacts(contacts);
  for (const fcl::Contactd& fc : contacts) {
    const bool aFirst = fc.o1 == gA.get();
    const auto bA = static_cast<int>(aFirst ? fc.b1 : fc.b2);
    const auto bB = static_cast<int>(aFirst ? fc.b2 : fc.b1);
    Contact c;
    c.a = A.id;
    c.b = B.id;
    c.triangleA = A.bvh && bA >= 0 ? A.bvhToMesh[static_cast<std::size_t>(bA)] : -1;
    c.triangleB = B.bvh && bB >= 0 ? B.bvhToMesh[static_cast<std::size_t>(bB)] : -1;
    c.position = fc.pos;
    c.penetration = std::max(0.0, fc.penetration_depth);
    c.allowance = tol.distance;
    // Coplanar: a mesh triangle against a box face.
    auto meshTriInBox = [&](const WorldObject& meshObj, const Eigen::Isometry3d& meshPose, int tri, const WorldObject& boxObj,
                            const Eigen::Isometry3d& boxPose) {
      const Eigen::Isometry3d toBox = boxObj.fclPose(boxPose).inverse() * meshPose;
      const auto& tr = meshObj.mesh->triangles[static_cast<std::size_t>(tri)];
      const Tri t{toBox * meshObj.mesh->vertices[static_cast<std::size_t>(tr[0])],
                  toBox * meshObj.mesh->vertices[static_cast<std::size_t>(tr[1])],
                  toBox * meshObj.mesh->vertices[static_cast<std::size_t>(tr[2])]};
      const Eigen::Vector3d n = toBox.linear() * meshObj.patches->normals[static_cast<std::size_t>(tri)];
      return coplanarWithBox(t, n, boxObj.boxHalf, cosAngle, tol.distance);
    };
    if (c.triangleA >= 0 && B.info.proxy == ProxyKind::Box) c.coplanar = meshTriInBox(A, poseA, c.triangleA, B, poseB);
    if (c.triangleB >= 0 && A.info.proxy == ProxyKind::Box) c.coplanar = meshTriInBox(B, poseB, c.triangleB, A, poseA);
    if (keep) {
      if (!c.coplanar) continue;
      c.penetration = 0.0;
    } else {
      ++out.intersecting;
      const bool skip = mode == FilterMode::SkipCoplanar && c.coplanar;
      if (skip || (opt.dropTouching && c.penetration <= c.allowance)) {
        ++out.filtered;
        continue;
      }
    }
    out.contacts.push_back(c);
    if (opt.stopAtFirst) break;
    if (out.contacts.size() >= opt.maxContacts) {
      out.truncated = true;
      break;
    }
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------------------
// CollisionWorld
// ---------------------------------------------------------------------------------------------------

CollisionWorld::CollisionWorld(const Assembly& assembly, const WorldOptions& options) : impl_(std::make_unique<Impl>()) {
  Impl& w = *impl_;
  w.tol = options.tolerances;
  w.base = assembly.base;
  w.parts.resize(assembly.parts.size());
  w.environment.resize(assembly.environment.size());
  auto simplifiedFor = [&](ObjectId id) -> std::shared_ptr<const TriMesh> {
    for (const auto& [oid, mesh] : options.simplified)
      if (oid == id) return mesh;
    return nullptr;
  };
  std::multimap<std::uint64_t, const WorldObject*> built;
  auto setupMesh = [&](WorldObject& o, const std::shared_ptr<const TriMesh>& display) {
    o.info.displayTriangles = display ? display->triangleCount() : 0;
    if (!display) {
      warn(w.diagnostics, Diagnostic::Severity::Error, displayName(o), "no-geometry", "a mesh", "none");
      o.info.proxy = ProxyKind::None;
      o.info.proxyReason = "no mesh";
      return;
    }
    if (auto simple = simplifiedFor(o.id)) {
      buildMesh(o, simple, options.patches, w.diagnostics);
      if (o.bvh) {
        o.info.proxy = ProxyKind::SimplifiedMesh;
        // Two-sided sampled distance between the simplified and the full mesh.
        WorldObject full;
        full.id = o.id;
        full.info.name = o.info.name;
        Diagnostics ignore;
        buildMesh(full, display, options.patches, ignore);
        double dev = full.bvh ? sampledDeviation(*simple, *full.bvh, 20000) : 0.0;
        if (full.bvh) dev = std::max(dev, sampledDeviation(*display, *o.bvh, 20000));
        o.info.deviation = dev;
        o.info.proxyReason = "simplified mesh, " + std::to_string(o.info.triangles) + " of " +
                             std::to_string(o.info.displayTriangles) + " triangles, deviation " + fmt(dev) + " m (sampled)";
        return;
      }
    }
    // Parts with the same mesh (one mesh file used many times: bolts, nuts) share its hierarchy and
    // patches: built once. Found by a hash of the geometry and confirmed by comparing it.
    const std::uint64_t key = meshHash(*display);
    const WorldObject* same = nullptr;
    for (auto [it, end] = built.equal_range(key); it != end && !same; ++it)
      if (it->second->mesh == display || (it->second->mesh->vertices == display->vertices && it->second->mesh->triangles == display->triangles))
        same = it->second;
    if (same) {
      const WorldObject& first = *same;
      o.mesh = first.mesh;
      o.bvh = first.bvh;
      o.geometry = first.geometry;
      o.bvhToMesh = first.bvhToMesh;
      o.patches = first.patches;
      o.nodePlane = first.nodePlane;
      o.nodeCylinder = first.nodeCylinder;
      o.localBounds = first.localBounds;
      o.info.proxy = first.info.proxy;
      o.info.triangles = first.info.triangles;
      o.info.planarPatches = first.info.planarPatches;
      o.info.cylindricalPatches = first.info.cylindricalPatches;
      o.info.proxyReason = "full mesh, shared with " + displayName(first);
      return;
    }
    buildMesh(o, display, options.patches, w.diagnostics);
    if (o.bvh) {
      o.info.proxy = ProxyKind::Mesh;
      o.info.proxyReason = "full mesh";
      built.emplace(key, &o);
    }
  };
  for (std::size_t i = 0; i < assembly.parts.size(); ++i) {
    const Part& p = assembly.parts[i];
    WorldObject& o = w.parts[i];
    o.id = ObjectId::part(i);
    o.info.id = o.id;
    o.info.name = p.name;
    o.pose = p.pose;
    o.com = p.mass.centerOfMass;
    setupMesh(o, p.mesh);
  }
  for (std::size_t i = 0; i < assembly.environment.size(); ++i) {
    const EnvironmentObject& e = assembly.environment[i];
    WorldObject& o = w.environment[i];
    o.id = ObjectId::environment(i);
    o.info.id = o.id;
    o.info.name = e.name;
    o.pose = e.pose;
    o.info.displayTriangles = e.mesh ? e.mesh->triangleCount() : 0;
    if (options.environmentPrimitives && !simplifiedFor(o.id) && e.mesh && tryPrimitive(o, e, w.diagnostics)) continue;
    setupMesh(o, e.mesh);
  }
  w.makeBroadPhase();
  // What the part inspector shows of a constrained part: how each of its constraints meets the base.
  if (w.base)
    for (const Constraint& c : assembly.constraints) {
      if (c.part >= w.parts.size()) continue;
      std::string& fit = w.parts[c.part].info.fit;
      fit += (fit.empty() ? "" : "; ") +
             describeFit(matchSupport(c, *w.base, patches(ObjectId::part(c.part)), patches(ObjectId::part(*w.base)), w.tol));
    }
}

void CollisionWorld::Impl::makeBroadPhase() {
  manager = std::make_unique<fcl::DynamicAABBTreeCollisionManagerd>();
  std::vector<fcl::CollisionObjectd*> all;
  for (auto* list : {&parts, &environment})
    for (WorldObject& o : *list) {
      if (!o.geometry) continue;
      o.object = std::make_unique<fcl::CollisionObjectd>(o.geometry, o.fclPose(o.pose));
      o.object->setUserData(&o);
      all.push_back(o.object.get());
    }
  manager->registerObjects(all);
  manager->setup();
}

CollisionWorld CollisionWorld::instance() const {
  CollisionWorld copy;
  Impl& w = *copy.impl_;
  w.tol = impl_->tol;
  w.diagnostics = impl_->diagnostics;
  w.base = impl_->base;
  // Geometry is immutable once built and held by shared_ptr: only the per-object indices are copied.
  const auto share = [](const WorldObject& from) {
    WorldObject o;
    o.id = from.id;
    o.info = from.info;
    o.mesh = from.mesh;
    o.bvh = from.bvh;
    o.geometry = from.geometry;
    o.bvhToMesh = from.bvhToMesh;
    o.patches = from.patches;
    o.nodePlane = from.nodePlane;
    o.nodeCylinder = from.nodeCylinder;
    o.pose = from.pose;
    o.geometryOffset = from.geometryOffset;
    o.localBounds = from.localBounds;
    o.boxHalf = from.boxHalf;
    o.com = from.com;
    return o;
  };
  w.parts.reserve(impl_->parts.size());
  for (const WorldObject& o : impl_->parts) w.parts.push_back(share(o));
  w.environment.reserve(impl_->environment.size());
  for (const WorldObject& o : impl_->environment) w.environment.push_back(share(o));
  w.makeBroadPhase();
  return copy;
}

CollisionWorld::CollisionWorld() : impl_(std::make_unique<Impl>()) {}

CollisionWorld::~CollisionWorld() = default;
CollisionWorld::CollisionWorld(CollisionWorld&&) noexcept = default;
CollisionWorld& CollisionWorld::operator=(CollisionWorld&&) noexcept = default;

std::size_t CollisionWorld::partCount() const { return impl_->parts.size(); }
std::size_t CollisionWorld::environmentCount() const { return impl_->environment.size(); }
std::optional<PartId> CollisionWorld::base() const { return impl_->base; }
const Tolerances& CollisionWorld::tolerances() const { return impl_->tol; }
const Diagnostics& CollisionWorld::diagnostics() const { return impl_->diagnostics; }
const ObjectInfo& CollisionWorld::info(ObjectId id) const { return impl_->get(id).info; }

const SurfacePatches* CollisionWorld::patches(ObjectId id) const {
  const WorldObject& o = impl_->get(id);
  return o.bvh ? o.patches.get() : nullptr;
}

const TriMesh* CollisionWorld::collisionMesh(ObjectId id) const {
  const WorldObject& o = impl_->get(id);
  return o.bvh ? o.mesh.get() : nullptr;
}

std::vector<ObjectId> CollisionWorld::objects() const {
  std::vector<ObjectId> ids;
  for (std::size_t i = 0; i < impl_->parts.size(); ++i) ids.push_back(ObjectId::part(i));
  for (std::size_t i = 0; i < impl_->environment.size(); ++i) ids.push_back(ObjectId::environment(i));
  return ids;
}

void CollisionWorld::setPose(ObjectId id, const Eigen::Isometry3d& pose) {
  WorldObject& o = impl_->get(id);
  o.pose = pose;
  if (!o.object) return;
  o.object->setTransform(o.fclPose(pose));
  o.object->computeAABB();
  impl_->manager->update(o.object.get());
}

const Eigen::Isometry3d& CollisionWorld::pose(ObjectId id) const { return impl_->get(id).pose; }

Eigen::AlignedBox3d CollisionWorld::worldBounds(ObjectId id) const { return worldBounds(id, impl_->get(id).pose); }

Eigen::AlignedBox3d CollisionWorld::worldBounds(ObjectId id, const Eigen::Isometry3d& pose) const {
  const WorldObject& o = impl_->get(id);
  if (!o.geometry) return {};
  // The object's own bounding box, turned: exact for quarter turns, at most sqrt(3) times larger otherwise
  // (cheap: eight corners, not every vertex).
  return transformedBox(o.localBounds, pose);
}

double CollisionWorld::maxRadius(ObjectId id, const Eigen::Vector3d& point) const {
  const WorldObject& o = impl_->get(id);
  double r = 0.0;
  if (o.mesh && o.bvh) {
    for (const auto& v : o.mesh->vertices)
      if (v.allFinite()) r = std::max(r, (v - point).norm());
  } else if (!o.localBounds.isEmpty()) {
    for (int i = 0; i < 8; ++i) r = std::max(r, (o.localBounds.corner(static_cast<Eigen::AlignedBox3d::CornerType>(i)) - point).norm());
  }
  return r;
}

double CollisionWorld::maxRadius(ObjectId id, const Axis& axis) const {
  const WorldObject& o = impl_->get(id);
  const Eigen::Vector3d u = axis.direction.normalized();
  auto radial = [&](const Eigen::Vector3d& v) {
    Eigen::Vector3d d = v - axis.point;
    return (d - u * u.dot(d)).norm();
  };
  double r = 0.0;
  if (o.mesh && o.bvh) {
    for (const auto& v : o.mesh->vertices)
      if (v.allFinite()) r = std::max(r, radial(v));
  } else if (!o.localBounds.isEmpty()) {
    for (int i = 0; i < 8; ++i) r = std::max(r, radial(o.localBounds.corner(static_cast<Eigen::AlignedBox3d::CornerType>(i))));
  }
  return r;
}

namespace {
struct NearData {
  std::vector<ObjectId> found;
  const fcl::CollisionObjectd* probe = nullptr;
};
bool nearCallback(fcl::CollisionObjectd* o1, fcl::CollisionObjectd* o2, void* data) {
  auto* d = static_cast<NearData*>(data);
  const fcl::CollisionObjectd* other = o1 == d->probe ? o2 : o1;
  if (const auto* obj = static_cast<const WorldObject*>(other->getUserData())) d->found.push_back(obj->id);
  return false;
}
}  // namespace

std::vector<ObjectId> CollisionWorld::near(const Eigen::AlignedBox3d& box, std::optional<ObjectId> except) const {
  if (box.isEmpty()) return {};
  auto shape = std::make_shared<fcl::Boxd>(box.sizes().cwiseMax(1e-12));
  fcl::Transform3d tf = fcl::Transform3d::Identity();
  tf.translation() = box.center();
  fcl::CollisionObjectd probe(shape, tf);
  NearData data;
  data.probe = &probe;
  impl_->manager->collide(&probe, &data, nearCallback);
  std::vector<ObjectId> out;
  for (const ObjectId& id : data.found)
    if (!except || !(id == *except)) out.push_back(id);
  // Deterministic order: parts by id, then environment objects.
  std::sort(out.begin(), out.end(), [](const ObjectId& a, const ObjectId& b) {
    return a.kind != b.kind ? a.kind < b.kind : a.index < b.index;
  });
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

QueryResult CollisionWorld::query(ObjectId a, ObjectId b, const QueryOptions& options) const {
  return query(a, impl_->get(a).pose, b, options);
}

namespace {
struct Cull {
  const std::vector<char>* bBelow = nullptr;
  const std::vector<std::pair<int, int>>* fit = nullptr;  // PairContext::fit
  double fitClearance = 0.0;
};
QueryResult runQuery(const Tolerances& tol, const WorldObject& A, const Eigen::Isometry3d& poseA, const WorldObject& B,
                     const QueryOptions& options, const Cull& cull);
}  // namespace

QueryResult CollisionWorld::query(ObjectId a, const Eigen::Isometry3d& poseA, ObjectId b, const QueryOptions& options) const {
  if (a == b) return {};
  return runQuery(impl_->tol, impl_->get(a), poseA, impl_->get(b), options, {});
}

namespace {
QueryResult runQuery(const Tolerances& tol, const WorldObject& A, const Eigen::Isometry3d& poseA, const WorldObject& B,
                     const QueryOptions& options, const Cull& cull) {
  QueryResult out;
  if (!A.geometry || !B.geometry) return out;
  if (A.bvh && B.bvh) {
    PairContext ctx;
    ctx.bBelow = cull.bBelow;
    ctx.fit = cull.fit;
    ctx.fitClearance = cull.fitClearance;
    ctx.A = &A;
    ctx.B = &B;
    ctx.mode = options.mode;
    ctx.opt = options;
    ctx.opt.maxContacts = std::max<std::size_t>(1, options.maxContacts);
    ctx.tol = tol;
    ctx.out = &out;
    meshMeshQuery(ctx, poseA, B.pose);
  } else {
    primitiveQuery(A, poseA, B, B.pose, options.mode, options, tol, out);
  }
  return out;
}
}  // namespace

QueryResult CollisionWorld::queryAll(ObjectId a, const QueryOptions& options) const {
  QueryResult all;
  Eigen::AlignedBox3d grown = worldBounds(a);
  if (grown.isEmpty()) return all;
  grown.min().array() -= impl_->tol.distance;
  grown.max().array() += impl_->tol.distance;
  for (const ObjectId& b : near(grown, a)) {
    QueryOptions o = options;
    o.maxContacts = options.maxContacts - std::min(options.maxContacts, all.contacts.size());
    if (o.maxContacts == 0) {
      all.truncated = true;
      break;
    }
    QueryResult r = query(a, b, o);
    all.intersecting += r.intersecting;
    all.filtered += r.filtered;
    all.boundingVolumeTests += r.boundingVolumeTests;
    all.leafTests += r.leafTests;
    all.truncated = all.truncated || r.truncated;
    all.contacts.insert(all.contacts.end(), r.contacts.begin(), r.contacts.end());
    if (options.stopAtFirst && !all.contacts.empty()) break;
  }
  return all;
}

double CollisionWorld::distance(ObjectId a, ObjectId b) const { return distance(a, impl_->get(a).pose, b); }

double CollisionWorld::distance(ObjectId a, const Eigen::Isometry3d& poseA, ObjectId b) const {
  const WorldObject& A = impl_->get(a);
  const WorldObject& B = impl_->get(b);
  if (!A.geometry || !B.geometry) return std::numeric_limits<double>::infinity();
  fcl::DistanceRequestd req;
  fcl::DistanceResultd res;
  fcl::distance(A.geometry.get(), A.fclPose(poseA), B.geometry.get(), B.fclPose(B.pose), req, res);
  return std::max(0.0, res.min_distance);
}

BlockResult CollisionWorld::blocked(const Support& s, std::size_t maxContacts) const {
  return blocked(s, impl_->get(ObjectId::part(s.part)).pose, maxContacts);
}

BlockResult CollisionWorld::blocked(const Support& s, const Eigen::Isometry3d& partPose, std::size_t maxContacts) const {
  BlockResult r;
  const ObjectId part = ObjectId::part(s.part), base = ObjectId::part(s.base);
  const Tolerances& tol = impl_->tol;
  Eigen::AlignedBox3d box = worldBounds(part, partPose);
  if (box.isEmpty()) return r;
  box.min().array() -= tol.distance;
  box.max().array() += tol.distance;
  for (const ObjectId& other : near(box, part)) {
    QueryOptions o;
    o.dropTouching = true;
    o.maxContacts = std::max<std::size_t>(1, maxContacts - std::min(maxContacts, r.contacts.size()));
    o.stopAtFirst = maxContacts <= 1;
    Eigen::Isometry3d pose = partPose;
    Cull cull;
    if (other == base) {
      const Eigen::Isometry3d& baseToWorld = impl_->get(base).pose;
      const SupportCache* cache = s.cache.get();
      if (s.kind == Support::Kind::Plane) {
        o.mode = FilterMode::SkipCoplanar;
        // Lift the part off the face it rests on by half the tolerance: exactly touching faces would
        // otherwise be visited pair by pair (tens of thousands of leaf tests on a fine mesh).
        const Eigen::Vector3d n = baseToWorld.linear() * s.basePlane.normal;
        pose.pretranslate(0.5 * tol.distance * n);
        // Skip the base's geometry below its face while the part is on its side of the face (FCL's
        // bounding boxes are about 1e-5 m loose, so the lift alone does not separate them).
        if (cache && cache->planeCull) {
          const Eigen::Isometry3d partToBase = baseToWorld.inverse() * pose;
          const Eigen::Vector3d np = partToBase.linear() * s.partPlane.normal;
          const double gap = s.basePlane.normal.dot(partToBase * s.partPlane.point - s.basePlane.point);
          const double sinTilt = s.basePlane.normal.cross(-np).norm();
          if (-np.dot(s.basePlane.normal) > 0.0 && gap - sinTilt * cache->partReach > 0.3 * tol.distance) cull.bBelow = &cache->baseBelow;
        }
      } else {
        o.mode = FilterMode::SkipCoaxial;
        cull.fit = &s.fitPairs;
        cull.fitClearance = s.clearance;
        if (cache && cache->axisCull) {
          // Every point of the part stays at least nearest - off - tilt * reach from the base's axis: no
          // closer than the shaft's surface (less a tenth of the tolerance), where only the fit can touch.
          const Eigen::Isometry3d partToBase = baseToWorld.inverse() * pose;
          const Eigen::Vector3d up = partToBase.linear() * s.partAxis.direction;
          Eigen::Vector3d off = partToBase * s.partAxis.point - s.baseAxis.point;
          off -= s.baseAxis.direction * s.baseAxis.direction.dot(off);
          const double sinTilt = up.cross(s.baseAxis.direction).norm();
          if (cache->partNearest - off.norm() - sinTilt * cache->partReach >= cache->fitRadius - 0.1 * tol.distance &&
              off.norm() <= s.clearance + 0.1 * tol.distance)
            cull.bBelow = &cache->baseInside;
        }
      }
    }
    QueryResult q = runQuery(impl_->tol, impl_->get(part), pose, impl_->get(other), o, cull);
    r.boundingVolumeTests += q.boundingVolumeTests;
    r.leafTests += q.leafTests;
    if (!q.contacts.empty() && !r.by) r.by = other;
    r.contacts.insert(r.contacts.end(), q.contacts.begin(), q.contacts.end());
    if (r.contacts.size() >= std::max<std::size_t>(1, maxContacts)) break;
  }
  r.blocked = !r.contacts.empty();
  return r;
}

BlockResult CollisionWorld::colliding(ObjectId id, const Eigen::Isometry3d& pose, bool countTouching) const {
  BlockResult r;
  Eigen::AlignedBox3d box = worldBounds(id, pose);
  if (box.isEmpty()) return r;
  box.min().array() -= impl_->tol.distance;
  box.max().array() += impl_->tol.distance;
  for (const ObjectId& other : near(box, id)) {
    QueryOptions o;
    o.dropTouching = !countTouching;
    o.maxContacts = 8;
    QueryResult q = query(id, pose, other, o);
    if (!q.contacts.empty() && !r.by) r.by = other;
    r.contacts.insert(r.contacts.end(), q.contacts.begin(), q.contacts.end());
  }
  r.blocked = !r.contacts.empty();
  return r;
}

namespace {

// Möller-Trumbore: the ray parameter where it crosses the triangle, from either side.
std::optional<double> rayTriangle(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& a,
                                  const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a;
  const Eigen::Vector3d p = d.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-300) return std::nullopt;
  const Eigen::Vector3d s = o - a;
  const double u = s.dot(p) / det;
  if (u < 0.0 || u > 1.0) return std::nullopt;
  const Eigen::Vector3d q = s.cross(e1);
  const double v = d.dot(q) / det;
  if (v < 0.0 || u + v > 1.0) return std::nullopt;
  const double t = e2.dot(q) / det;
  return t >= 0.0 ? std::optional<double>(t) : std::nullopt;
}

// Ray against a primitive centred at the origin of its frame (o, d in that frame).
std::optional<double> rayPrimitive(const fcl::CollisionGeometryd& g, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  if (const auto* box = dynamic_cast<const fcl::Boxd*>(&g)) {
    const Eigen::Vector3d h = box->side / 2.0;
    double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 3; ++i) {
      if (std::abs(d[i]) < 1e-300) {
        if (std::abs(o[i]) > h[i]) return std::nullopt;
        continue;
      }
      double a = (-h[i] - o[i]) / d[i], b = (h[i] - o[i]) / d[i];
      if (a > b) std::swap(a, b);
      t0 = std::max(t0, a);
      t1 = std::min(t1, b);
      if (t0 > t1) return std::nullopt;
    }
    return t0;
  }
  if (const auto* sphere = dynamic_cast<const fcl::Sphered*>(&g)) {
    const double b = o.dot(d), c = o.squaredNorm() - sphere->radius * sphere->radius;
    const double disc = b * b - c;
    if (disc < 0.0) return std::nullopt;
    const double t = -b - std::sqrt(disc);
    return t >= 0.0 ? t : (c <= 0.0 ? std::optional<double>(0.0) : std::nullopt);
  }
  if (const auto* cyl = dynamic_cast<const fcl::Cylinderd*>(&g)) {
    const double r = cyl->radius, hz = cyl->lz / 2.0;
    std::optional<double> best;
    const auto consider = [&](double t) {
      if (t >= 0.0 && (!best || t < *best)) best = t;
    };
    const double a = d.x() * d.x() + d.y() * d.y();
    if (a > 1e-300) {
      const double b = o.x() * d.x() + o.y() * d.y(), c = o.x() * o.x() + o.y() * o.y() - r * r;
      const double disc = b * b - a * c;
      if (disc >= 0.0)
        for (double t : {(-b - std::sqrt(disc)) / a, (-b + std::sqrt(disc)) / a})
          if (std::abs(o.z() + t * d.z()) <= hz) consider(t);
    }
    if (std::abs(d.z()) > 1e-300)
      for (double z : {-hz, hz}) {
        const double t = (z - o.z()) / d.z();
        const Eigen::Vector3d p = o + t * d;
        if (p.x() * p.x() + p.y() * p.y() <= r * r) consider(t);
      }
    return best;
  }
  return std::nullopt;
}

}  // namespace

std::optional<CollisionWorld::RayHit> CollisionWorld::castRay(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                                                              double length, std::optional<ObjectId> except) const {
  if (!(length > 0.0) || !origin.allFinite() || !direction.allFinite() || direction.norm() < 1e-12) return std::nullopt;
  const Eigen::Vector3d d = direction.normalized();
  Eigen::AlignedBox3d box(origin);
  box.extend(origin + d * length);
  // A thin box along the ray finds the triangles it may cross (FCL has no ray query).
  constexpr double kWidth = 1e-4;
  auto thin = std::make_shared<fcl::Boxd>(kWidth, kWidth, length);
  fcl::Transform3d tf = fcl::Transform3d::Identity();
  tf.linear() = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), d).toRotationMatrix();
  tf.translation() = origin + d * (length / 2.0);
  std::optional<RayHit> best;
  const auto consider = [&](ObjectId id, double t) {
    if (t <= length && (!best || t < best->distance)) best = RayHit{id, origin + d * t, t};
  };
  for (const ObjectId& id : near(box.extend(box.min() - Eigen::Vector3d::Constant(kWidth))
                                     .extend(box.max() + Eigen::Vector3d::Constant(kWidth)),
                                 except)) {
    const WorldObject& o = impl_->get(id);
    if (!o.geometry) continue;
    const Eigen::Isometry3d toGeometry = o.fclPose(o.pose).inverse();
    if (!o.bvh) {
      if (const auto t = rayPrimitive(*o.geometry, toGeometry * origin, toGeometry.linear() * d)) consider(id, *t);
      continue;
    }
    fcl::CollisionRequestd req(256, true);
    fcl::CollisionResultd res;
    fcl::collide(thin.get(), tf, o.geometry.get(), o.fclPose(o.pose), req, res);
    std::vector<fcl::Contactd> contacts;
    res.getContacts(contacts);
    const Eigen::Vector3d lo = o.pose.inverse() * origin, ld = o.pose.linear().transpose() * d;
    for (const fcl::Contactd& c : contacts) {
      const auto prim = static_cast<std::size_t>(c.o1 == thin.get() ? c.b2 : c.b1);
      if (prim >= o.bvhToMesh.size()) continue;
      const Eigen::Vector3i& tri = o.mesh->triangles[static_cast<std::size_t>(o.bvhToMesh[prim])];
      const auto& v = o.mesh->vertices;
      if (const auto t = rayTriangle(lo, ld, v[static_cast<std::size_t>(tri[0])], v[static_cast<std::size_t>(tri[1])],
                                     v[static_cast<std::size_t>(tri[2])]))
        consider(id, *t);
    }
  }
  return best;
}

Eigen::Vector3d CollisionWorld::centreOfMass(PartId p) const { return impl_->get(ObjectId::part(p)).com; }

namespace {
// A flag per BVH node: a leaf's from its triangle, an inner node's from both children (FCL stores
// children after their parent, so one backward pass suffices).
template <class LeafFlag>
std::vector<char> nodeFlags(const WorldObject& o, const LeafFlag& leaf) {
  const Model& m = *o.bvh;
  std::vector<char> flags(static_cast<std::size_t>(m.getNumBVs()), 0);
  for (int i = m.getNumBVs() - 1; i >= 0; --i) {
    const auto& node = m.getBV(i);
    const auto k = static_cast<std::size_t>(i);
    if (node.isLeaf()) flags[k] = leaf(o.bvhToMesh[static_cast<std::size_t>(node.primitiveId())]) ? 1 : 0;
    else flags[k] = flags[static_cast<std::size_t>(node.first_child)] && flags[static_cast<std::size_t>(node.first_child + 1)] ? 1 : 0;
  }
  return flags;
}
}  // namespace

namespace {

// Two unit vectors that make (a, b, u) orthonormal.
std::pair<Eigen::Vector3d, Eigen::Vector3d> basisAround(const Eigen::Vector3d& u) {
  const Eigen::Vector3d helper = std::abs(u.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d a = u.cross(helper).normalized();
  return {a, u.cross(a)};
}

// Nearest distance of a triangle from the origin of its plane of projection (0 when it covers it).
double nearestToOrigin(const geom2::P& p, const geom2::P& q, const geom2::P& r) {
  const geom2::P o(0.0, 0.0);
  const double c1 = geom2::cross(q - p, o - p), c2 = geom2::cross(r - q, o - q), c3 = geom2::cross(p - r, o - r);
  if ((c1 >= 0.0 && c2 >= 0.0 && c3 >= 0.0) || (c1 <= 0.0 && c2 <= 0.0 && c3 <= 0.0)) return 0.0;
  return std::min({geom2::distanceToSegment(o, p, q), geom2::distanceToSegment(o, q, r), geom2::distanceToSegment(o, r, p)});
}

double boxDistance(const geom2::Box& a, const geom2::Box& b) {
  const double dx = std::max({0.0, a.lo.x() - b.hi.x(), b.lo.x() - a.hi.x()});
  const double dy = std::max({0.0, a.lo.y() - b.hi.y(), b.lo.y() - a.hi.y()});
  return std::hypot(dx, dy);
}

// How far `a` may slide, in any direction, before it has entered `b` by `enter`: from boxes that at most
// touch; none (a negative number) when their insides already overlap.
double slideBeforeEntering(const geom2::Box& a, const geom2::Box& b, double enter) {
  const double gap = std::max({a.lo.x() - b.hi.x(), b.lo.x() - a.hi.x(), a.lo.y() - b.hi.y(), b.lo.y() - a.hi.y()});
  return gap < 0.0 ? -1.0 : boxDistance(a, b) + enter;
}

// Overlapping or touching spans merged, in order.
std::vector<SupportCache::Span> merged(std::vector<SupportCache::Span> spans) {
  std::sort(spans.begin(), spans.end(), [](const auto& a, const auto& b) { return a.lo < b.lo; });
  std::vector<SupportCache::Span> out;
  for (const auto& sp : spans) {
    if (!out.empty() && sp.lo <= out.back().hi) out.back().hi = std::max(out.back().hi, sp.hi);
    else out.push_back(sp);
  }
  return out;
}

// The free-motion data of an axis support (SupportCache): the part's band and extent about its axis, the
// base's faces within the band, the fit's spans.
void prepareAxisFreeMotion(SupportCache& c, const Support& s, const WorldObject& part, const WorldObject& base, double tol,
                           bool excludeFit) {
  const Eigen::Vector3d up = s.partAxis.direction, op = s.partAxis.point;
  const Eigen::Vector3d ub = s.baseAxis.direction, ob = s.baseAxis.point;
  const auto [pa, pb] = basisAround(up);
  const auto [ba, bb] = basisAround(ub);
  const TriMesh& pm = *part.mesh;
  const SurfacePatches& pp = *part.patches;
  double bandMin = 1e300, bandMax = 0.0, e0 = 1e300, e1 = -1e300;
  for (std::size_t t = 0; t < pm.triangles.size(); ++t) {
    if (pp.planeOf[t] < 0) continue;  // degenerate: not in the hierarchy either
    geom2::P q[3];
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d d = pm.vertices[static_cast<std::size_t>(pm.triangles[t][k])] - op;
      q[k] = {pa.dot(d), pb.dot(d)};
      bandMax = std::max(bandMax, q[k].norm());
      e0 = std::min(e0, up.dot(d));
      e1 = std::max(e1, up.dot(d));
    }
    bandMin = std::min(bandMin, nearestToOrigin(q[0], q[1], q[2]));
  }
  if (!(bandMin <= bandMax)) return;
  c.bandMin = bandMin;
  c.bandMax = bandMax;
  c.partSpan = {e0, e1};
  // The base's faces within the band (the widest play included), but not the fit's own cylinders when the
  // part lies entirely on their far side: there it can touch them only along the fit, which the blocked
  // check ignores.
  std::vector<char> skip(base.patches->planes.size(), 0);
  if (excludeFit)
    for (int j : s.basePatches)
      for (int f : base.patches->cylinders[static_cast<std::size_t>(j)].facets) skip[static_cast<std::size_t>(f)] = 1;
  const double lo = bandMin - s.clearance - tol, hi = bandMax + s.clearance + tol;
  std::vector<SupportCache::Span> obstacles;
  const TriMesh& bm = *base.mesh;
  for (std::size_t k = 0; k < base.patches->planes.size(); ++k) {
    if (skip[k]) continue;
    double rmin = 1e300, rmax = 0.0, zlo = 1e300, zhi = -1e300;
    for (int t : base.patches->planes[k].triangles) {
      geom2::P q[3];
      for (int i = 0; i < 3; ++i) {
        const Eigen::Vector3d d = bm.vertices[static_cast<std::size_t>(bm.triangles[static_cast<std::size_t>(t)][i])] - ob;
        q[i] = {ba.dot(d), bb.dot(d)};
        rmax = std::max(rmax, q[i].norm());
        zlo = std::min(zlo, ub.dot(d));
        zhi = std::max(zhi, ub.dot(d));
      }
      rmin = std::min(rmin, nearestToOrigin(q[0], q[1], q[2]));
    }
    if (rmin <= hi && rmax >= lo) obstacles.push_back({zlo, zhi});
  }
  c.axialObstacles = merged(std::move(obstacles));
  for (const auto& [i, j] : s.fitPairs) {
    const CylindricalPatch& a = pp.cylinders[static_cast<std::size_t>(i)];
    const CylindricalPatch& b = base.patches->cylinders[static_cast<std::size_t>(j)];
    const double a0 = up.dot(a.point - op), a1 = up.dot(a.point + a.length * a.direction - op);
    const double b0 = ub.dot(b.point - ob), b1 = ub.dot(b.point + b.length * b.direction - ob);
    c.fitSpans.push_back({{std::min(a0, a1), std::max(a0, a1)}, {std::min(b0, b1), std::max(b0, b1)}});
  }
  c.free = true;
}

bool convexLoop(const std::vector<geom2::P>& loop) {
  if (loop.size() < 3) return false;
  const double a = std::abs(geom2::area(loop)), h = std::abs(geom2::area(geom2::convexHull(loop)));
  return h > 0.0 && h - a <= 1e-9 * h;
}

// The free-motion data of a plane support: the part's height, the base's faces that rise into it, the
// support face's outline.
void preparePlaneFreeMotion(SupportCache& c, const Support& s, const WorldObject& part, const WorldObject& base, double tol) {
  const Eigen::Vector3d nb = s.basePlane.normal, ob = s.basePlane.point;
  std::tie(c.e1, c.e2) = basisAround(nb);
  double height = 0.0;
  for (const auto& v : part.mesh->vertices)
    if (v.allFinite()) height = std::max(height, -s.partPlane.normal.dot(v - s.partPlane.point));
  c.partHeight = height;
  const auto to2 = [&](const Eigen::Vector3d& x) { return geom2::P(c.e1.dot(x - ob), c.e2.dot(x - ob)); };
  const TriMesh& bm = *base.mesh;
  for (const PlanarPatch& patch : base.patches->planes) {
    geom2::Box box;
    double hlo = 1e300, hhi = -1e300;
    for (int t : patch.triangles)
      for (int i = 0; i < 3; ++i) {
        const Eigen::Vector3d& v = bm.vertices[static_cast<std::size_t>(bm.triangles[static_cast<std::size_t>(t)][i])];
        box.extend(to2(v));
        hlo = std::min(hlo, nb.dot(v - ob));
        hhi = std::max(hhi, nb.dot(v - ob));
      }
    if (hhi > 0.25 * tol && hlo < height + tol) c.planeObstacles.push_back(box);
  }
  for (int k : s.basePatches) {
    const PlanarPatch& patch = base.patches->planes[static_cast<std::size_t>(k)];
    for (const Outline& loop : patch.outline)
      for (std::size_t i = 0; i < loop.size(); ++i)
        c.baseOutline.push_back({to2(patch.toMesh(loop[i])), to2(patch.toMesh(loop[(i + 1) % loop.size()]))});
  }
  if (s.basePatches.size() == 1) {
    const PlanarPatch& patch = base.patches->planes[static_cast<std::size_t>(s.basePatches[0])];
    if (patch.outline.size() == 1) {
      std::vector<geom2::P> pts;
      for (const auto& q : patch.outline[0]) pts.push_back(to2(patch.toMesh(q)));
      if (convexLoop(pts)) c.convexBase = geom2::convexHull(pts);
    }
  }
  if (s.partPatches.size() == 1) {
    const PlanarPatch& patch = part.patches->planes[static_cast<std::size_t>(s.partPatches[0])];
    c.partFaceConvex = patch.outline.size() == 1 && convexLoop(patch.outline[0]);
  }
  c.free = true;
}

}  // namespace

void CollisionWorld::prepare(Support& s) const {
  if (!s.problem.empty()) return;
  const WorldObject& part = impl_->get(ObjectId::part(s.part));
  const WorldObject& base = impl_->get(ObjectId::part(s.base));
  if (!part.bvh || !base.bvh) return;
  auto cache = std::make_shared<SupportCache>();
  const double tol = impl_->tol.distance;
  if (s.kind == Support::Kind::Axis) {
    const Eigen::Vector3d ub = s.baseAxis.direction, ob = s.baseAxis.point;
    const Eigen::Vector3d up = s.partAxis.direction, op = s.partAxis.point;
    auto radial = [](const Eigen::Vector3d& x, const Eigen::Vector3d& o, const Eigen::Vector3d& u) {
      Eigen::Vector3d d = x - o;
      return (d - u * u.dot(d)).norm();
    };
    double r = 0.0;
    for (int i : s.basePatches) r = std::max(r, base.patches->cylinders[static_cast<std::size_t>(i)].radius);
    const TriMesh& bm = *base.mesh;
    cache->baseInside = nodeFlags(base, [&](int tri) {
      const Eigen::Vector3i& t = bm.triangles[static_cast<std::size_t>(tri)];
      for (int k = 0; k < 3; ++k)
        if (radial(bm.vertices[static_cast<std::size_t>(t[k])], ob, ub) > r + 0.25 * tol) return false;
      return true;
    });
    double nearest = 1e300, farthest = 0.0, reach = 0.0;
    for (int i = 0; i < part.bvh->num_vertices; ++i) {
      const fcl::Vector3d& v = part.bvh->vertices[i];
      nearest = std::min(nearest, radial(v, op, up));
      farthest = std::max(farthest, radial(v, op, up));
      reach = std::max(reach, (v - op).norm());
    }
    cache->partReach = reach;
    cache->partNearest = nearest;
    cache->fitRadius = r;
    cache->axisCull = nearest >= r - 0.1 * tol;
    // A sleeve entirely outside its shaft, or a pin entirely inside its bore, meets the fit's cylinders
    // only along the fit.
    prepareAxisFreeMotion(*cache, s, part, base, tol, s.partIsBore ? nearest >= r - 0.1 * tol : farthest <= r + 0.1 * tol);
    s.cache = std::move(cache);
    return;
  }
  {
    const Eigen::Vector3d n = s.basePlane.normal;
    const double limit = n.dot(s.basePlane.point) + 0.25 * tol;
    const TriMesh& bm = *base.mesh;
    cache->baseBelow = nodeFlags(base, [&](int tri) {
      const Eigen::Vector3i& t = bm.triangles[static_cast<std::size_t>(tri)];
      for (int k = 0; k < 3; ++k)
        if (n.dot(bm.vertices[static_cast<std::size_t>(t[k])]) > limit) return false;
      return true;
    });
    // The part must lie on its side of its own contact plane (not hang over the base's edge below it).
    double lowest = 0.0, reach = 0.0;
    for (int i = 0; i < part.bvh->num_vertices; ++i) {
      const fcl::Vector3d& v = part.bvh->vertices[i];
      lowest = std::min(lowest, -s.partPlane.normal.dot(v - s.partPlane.point));
      reach = std::max(reach, (v - s.partPlane.point).norm());
    }
    cache->partReach = reach;
    cache->planeCull = lowest >= -0.1 * tol;
    preparePlaneFreeMotion(*cache, s, part, base, tol);
  }
  s.cache = std::move(cache);
}

FreeMotion CollisionWorld::freeMotion(const Support& s, const Eigen::Isometry3d& partPose) const {
  FreeMotion f;
  const SupportCache* c = s.cache.get();
  if (!s.problem.empty() || !c || !c->free) return f;
  const double tol = impl_->tol.distance;
  const ObjectId part = ObjectId::part(s.part), base = ObjectId::part(s.base);
  const Eigen::Isometry3d& baseToWorld = impl_->get(base).pose;
  const Eigen::Isometry3d partToBase = baseToWorld.inverse() * partPose;
  // The other objects whose boxes reach `sweptBase` (a box in the base's frame, given by corners).
  const auto others = [&](const std::array<Eigen::Vector3d, 8>& sweptBase) {
    Eigen::AlignedBox3d box;
    for (const auto& q : sweptBase) box.extend(baseToWorld * q);
    std::vector<std::array<Eigen::Vector3d, 8>> out;
    for (const ObjectId& o : near(box, part)) {
      if (o == base) continue;
      const Eigen::AlignedBox3d b = worldBounds(o);
      std::array<Eigen::Vector3d, 8> corners;
      for (int i = 0; i < 8; ++i) corners[static_cast<std::size_t>(i)] = baseToWorld.inverse() * b.corner(static_cast<Eigen::AlignedBox3d::CornerType>(i));
      out.push_back(corners);
    }
    return out;
  };

  if (s.kind == Support::Kind::Axis) {
    const Eigen::Vector3d ub = s.baseAxis.direction, ob = s.baseAxis.point;
    const double along = (partToBase.linear() * s.partAxis.direction).dot(ub);
    // The band argument needs the axes parallel (the world's poses are, to rounding).
    if (std::abs(along) < 1.0 - 1e-12) return f;
    const double sign = along > 0.0 ? 1.0 : -1.0;
    const Eigen::Vector3d op = partToBase * s.partAxis.point;
    const double t = ub.dot(op - ob);
    const double off = ((op - ob) - ub * t).norm();
    if (off > s.clearance + 0.5 * tol) return f;
    const auto inBase = [&](const SupportCache::Span& sp) {
      const double a = t + sign * sp.lo, b = t + sign * sp.hi;
      return SupportCache::Span{std::min(a, b), std::max(a, b)};
    };
    // Touch holds while some fit pair's axial overlap stays above -tol: a slide d within each pair's span.
    double lo = 1e300, hi = -1e300;
    for (const auto& [ps, bs] : c->fitSpans) {
      const SupportCache::Span p = inBase(ps);
      const double a = bs.lo - p.hi - tol, b = bs.hi - p.lo + tol;
      if (a <= 0.0 && b >= 0.0) {
        lo = std::min(lo, a);
        hi = std::max(hi, b);
      }
    }
    if (!(lo <= hi)) return f;
    // Obstacles: the part's extent, slid by d, stays clear of every span within its band, or enters it by
    // at most half a tolerance: from where their extents only touch, a slide of d makes no two triangles
    // pass through each other deeper than d, and a pair blocks only beyond its allowance (at least a
    // tolerance). So the free motion ends inside the contact, and a search beyond it starts at the event.
    const SupportCache::Span ext = inBase(c->partSpan);
    const double enter = 0.5 * tol;
    FreeMotion::Bound atMin = FreeMotion::Bound::Touch, atMax = FreeMotion::Bound::Touch;
    bool overlapping = false;
    const auto obstacle = [&](double zlo, double zhi) {
      if (zhi <= ext.lo) {
        if (zhi - enter - ext.lo > lo) {
          lo = zhi - enter - ext.lo;
          atMin = FreeMotion::Bound::Obstacle;
        }
      } else if (zlo >= ext.hi) {
        if (zlo + enter - ext.hi < hi) {
          hi = zlo + enter - ext.hi;
          atMax = FreeMotion::Bound::Obstacle;
        }
      } else {
        overlapping = true;
      }
    };
    for (const auto& o : c->axialObstacles) obstacle(o.lo, o.hi);
    if (overlapping) return f;
    // The other objects whose boxes come within the band along the way.
    const double R = c->bandMax + off + tol;
    const auto [a, b] = basisAround(ub);
    std::array<Eigen::Vector3d, 8> swept;
    for (int i = 0; i < 8; ++i)
      swept[static_cast<std::size_t>(i)] = ob + ub * ((i & 1) ? ext.hi + hi : ext.lo + lo) + a * ((i & 2) ? R : -R) + b * ((i & 4) ? R : -R);
    for (const auto& corners : others(swept)) {
      Eigen::Vector3d centre = Eigen::Vector3d::Zero();
      double zlo = 1e300, zhi = -1e300;
      for (const auto& q : corners) {
        centre += q / 8.0;
        zlo = std::min(zlo, ub.dot(q - ob));
        zhi = std::max(zhi, ub.dot(q - ob));
      }
      const double halfDiagonal = (corners[0] - centre).norm();
      const Eigen::Vector3d radial = (centre - ob) - ub * ub.dot(centre - ob);
      if (radial.norm() - halfDiagonal <= R) obstacle(zlo, zhi);
    }
    if (overlapping || lo > 0.0 || hi < 0.0) return f;
    f.axialMin = lo;
    f.axialMax = hi;
    f.atMin = atMin;
    f.atMax = atMax;
    return f;
  }

  const Eigen::Vector3d nb = s.basePlane.normal, ob = s.basePlane.point;
  if (-(partToBase.linear() * s.partPlane.normal).dot(nb) < 1.0 - 1e-12) return f;
  if (std::abs(nb.dot(partToBase * s.partPlane.point - ob) - s.offset) > 0.25 * tol) return f;
  // A part that reaches below its own contact plane could meet the faces under the base's.
  if (!c->planeCull || !touching(s, partPose).touching) return f;
  const auto to2 = [&](const Eigen::Vector3d& x) { return geom2::P(c->e1.dot(x - ob), c->e2.dot(x - ob)); };
  geom2::Box footprint;
  const Eigen::AlignedBox3d& local = impl_->get(part).localBounds;
  for (int i = 0; i < 8; ++i) footprint.extend(to2(partToBase * local.corner(static_cast<Eigen::AlignedBox3d::CornerType>(i))));
  double block = 1e300, touch = 1e300;
  // As along an axis, the part may enter an obstacle's box by half a tolerance before anything can block it.
  for (const geom2::Box& o : c->planeObstacles) block = std::min(block, slideBeforeEntering(footprint, o, 0.5 * tol));
  // Touch stays while no edge of the base's face comes near the part's; on a convex face with a convex
  // part face, also while the centre of mass stays inside the base's face (then it is inside the overlap
  // of the two faces, whose hull is the support polygon): that bound is where touch ends.
  for (const geom2::Segment& e : c->baseOutline) touch = std::min(touch, boxDistance(footprint, geom2::boxOf(e)) - tol);
  bool touchEnds = false;
  if (!c->convexBase.empty() && c->partFaceConvex) {
    const double inside = geom2::signedDistanceConvex(to2(partToBase * centreOfMass(s.part)), c->convexBase);
    touchEnds = inside > touch;
    touch = std::max(touch, inside);
  }
  double radius = std::min(block, touch);
  if (radius > 0.0) {
    const geom2::Box reach = footprint.inflated(radius);
    std::array<Eigen::Vector3d, 8> swept;
    for (int i = 0; i < 8; ++i)
      swept[static_cast<std::size_t>(i)] = ob + c->e1 * ((i & 1) ? reach.hi.x() : reach.lo.x()) +
                                           c->e2 * ((i & 2) ? reach.hi.y() : reach.lo.y()) + nb * ((i & 4) ? c->partHeight + tol : -tol);
    for (const auto& corners : others(swept)) {
      geom2::Box box;
      double hlo = 1e300, hhi = -1e300;
      for (const auto& q : corners) {
        box.extend(to2(q));
        hlo = std::min(hlo, nb.dot(q - ob));
        hhi = std::max(hhi, nb.dot(q - ob));
      }
      if (hhi > -tol && hlo < c->partHeight + tol) block = std::min(block, slideBeforeEntering(footprint, box, 0.5 * tol));
    }
    radius = std::min(block, touch);
  }
  if (!(radius > 0.0)) return f;
  f.radius = radius;
  f.atMax = block <= touch ? FreeMotion::Bound::Obstacle : touchEnds ? FreeMotion::Bound::Touch : FreeMotion::Bound::Conservative;
  return f;
}

}  // namespace vaw::collision
