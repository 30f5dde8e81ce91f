// The collision world's object store: building each object's geometry (BVH, surface patches, proxies), the
// broad phase, instances, poses, bounds and the objects near a box.
#include "collision_world_impl.hpp"

#include "../base/on_cores.hpp"

#include <deque>
#include <mutex>
#include <unordered_map>

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

namespace detail {
std::string fmt(double v) {
  std::ostringstream s;
  s.precision(4);
  s << v;
  return s.str();
}
}  // namespace detail

namespace {

using detail::fmt;

// FCL splits every node of a hierarchy across its longest axis at the mean of its triangles' centroids. A
// thin part (a gear, a plate, a washer) then keeps both its faces in every node until the nodes are as
// narrow as the part is thick, and each of those nodes' swept-sphere bound is as thick as the part: two
// such parts facing each other a few centimetres apart cost a distance query a hundred thousand node pairs
// or more (docs/collision.md, "Hierarchies"). This rule splits across whichever of the node's axes leaves
// clearly thinner children (half the sum of child count times child thickness, or less, of the axis chosen
// before it, the longest first), so that a thin part's faces part early.
// FCL's base has no virtual destructor; the hierarchy holds the splitter in a shared_ptr made from the
// derived type, which destroys it as what it is.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wnon-virtual-dtor"
class ThinChildrenSplitter final : public fcl::detail::BVSplitterBase<fcl::OBBRSSd> {
 public:
  void set(fcl::Vector3d* vertices, fcl::Triangle* triangles, fcl::BVHModelType) override {
    vertices_ = vertices;
    triangles_ = triangles;
  }

  void computeRule(const fcl::OBBRSSd& bv, unsigned int* primitives, int count) override {
    centroids_.resize(static_cast<std::size_t>(count));
    for (std::size_t i = 0; i < centroids_.size(); ++i) {
      const fcl::Triangle& t = triangles_[primitives[i]];
      centroids_[i] = (vertices_[t[0]] + vertices_[t[1]] + vertices_[t[2]]) / 3.0;
    }
    double chosen = std::numeric_limits<double>::infinity();
    for (int axis = 0; axis < 3; ++axis) {
      const Eigen::Vector3d dir = bv.obb.axis.col(axis);
      double mean = 0.0;
      for (const Eigen::Vector3d& c : centroids_) mean += dir.dot(c);
      mean /= static_cast<double>(count);
      const double cost = thickness(dir, mean);
      if (axis == 0 || cost < 0.5 * chosen) {
        chosen = cost;
        direction_ = dir;
        value_ = mean;
      }
    }
  }

  bool apply(const fcl::Vector3d& q) const override { return direction_.dot(q) > value_; }

  void clear() override {
    vertices_ = nullptr;
    triangles_ = nullptr;
  }

 private:
  // Over the two children the split makes: child count times child thickness, the spread of its
  // centroids across their thinnest direction.
  double thickness(const Eigen::Vector3d& dir, double at) const {
    Eigen::Matrix3d second[2] = {Eigen::Matrix3d::Zero(), Eigen::Matrix3d::Zero()};
    Eigen::Vector3d first[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
    double n[2] = {0.0, 0.0};
    for (const Eigen::Vector3d& c : centroids_) {
      const int side = dir.dot(c) > at ? 1 : 0;
      n[side] += 1.0;
      first[side] += c;
      second[side] += c * c.transpose();
    }
    double cost = 0.0;
    for (int side = 0; side < 2; ++side) {
      if (n[side] < 2.0) continue;
      const Eigen::Vector3d m = first[side] / n[side];
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
      eig.computeDirect(second[side] / n[side] - m * m.transpose(), Eigen::EigenvaluesOnly);
      cost += n[side] * std::sqrt(std::max(0.0, eig.eigenvalues()(0)));
    }
    return cost;
  }

  fcl::Vector3d* vertices_ = nullptr;
  fcl::Triangle* triangles_ = nullptr;
  std::vector<Eigen::Vector3d> centroids_;
  Eigen::Vector3d direction_ = Eigen::Vector3d::UnitX();
  double value_ = 0.0;
};
#pragma GCC diagnostic pop

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
// `cad`: the part's CAD solid, whose exact cylinders the patches take when `mesh` is its tessellation.
void buildMesh(WorldObject& o, std::shared_ptr<const TriMesh> mesh, const PatchOptions& popts, Diagnostics& diags,
               const CadSolid* cad = nullptr) {
  const auto t0 = std::chrono::steady_clock::now();
  o.mesh = std::move(mesh);
  const TriMesh& m = *o.mesh;
  o.patches = std::make_shared<const SurfacePatches>(classifySurfaces(m, cad, popts));
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
  bvh->bv_splitter = std::make_shared<ThinChildrenSplitter>();
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
  auto boxes = std::make_shared<std::vector<Eigen::AlignedBox3d>>(static_cast<std::size_t>(nodes));
  for (int i = nodes - 1; i >= 0; --i) {
    const auto& node = bvh->getBV(i);
    const auto k = static_cast<std::size_t>(i);
    if (node.isLeaf()) {
      const auto tri = static_cast<std::size_t>(o.bvhToMesh[static_cast<std::size_t>(node.primitiveId())]);
      o.nodePlane[k] = o.patches->planeOf[tri];
      o.nodeCylinder[k] = o.patches->cylinderOf[tri];
      for (int c = 0; c < 3; ++c) (*boxes)[k].extend(verts[static_cast<std::size_t>(tris[static_cast<std::size_t>(node.primitiveId())][c])]);
    } else {
      const auto c0 = static_cast<std::size_t>(node.first_child), c1 = c0 + 1;
      o.nodePlane[k] = o.nodePlane[c0] == o.nodePlane[c1] ? o.nodePlane[c0] : -1;
      o.nodeCylinder[k] = o.nodeCylinder[c0] == o.nodeCylinder[c1] ? o.nodeCylinder[c0] : -1;
      (*boxes)[k] = (*boxes)[c0].merged((*boxes)[c1]);
    }
  }
  o.nodeBox = std::move(boxes);
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

// A mesh's hierarchy and surface patches as buildMesh made them, kept while the mesh lives: a CAD product's
// mesh goes into several worlds while it opens (units, who goes first, the check at rest, the window's
// scene), and building it again for each was a fifth of those stages on a real export. Keyed by the mesh
// (held weakly, so a mesh at a freed one's address is not taken for it), its CAD solid and the options.
struct BuiltMesh {
  std::weak_ptr<const TriMesh> mesh;
  const CadSolid* cad = nullptr;
  PatchOptions options;
  WorldObject built;        // the geometry fields only
  Diagnostics diagnostics;  // what building it reported, `file` naming the object that was built
};

class BuiltMeshes {
 public:
  // Fills `o` from a kept build of `mesh` and appends its diagnostics renamed for `o`; false when none.
  bool take(WorldObject& o, const std::shared_ptr<const TriMesh>& mesh, const CadSolid* cad, const PatchOptions& options,
            Diagnostics& diags) {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = kept_.find(mesh.get());
    if (it == kept_.end()) return false;
    const BuiltMesh& b = it->second;
    if (b.mesh.lock() != mesh || b.cad != cad || !same(b.options, options)) return false;
    copyGeometry(o, b.built);
    o.info.proxyReason = b.built.info.proxyReason;
    o.info.buildSeconds = b.built.info.buildSeconds;
    for (Diagnostic d : b.diagnostics) {
      d.file = displayName(o);
      diags.push_back(std::move(d));
    }
    return true;
  }
  void keep(const WorldObject& o, const CadSolid* cad, const PatchOptions& options, Diagnostics diagnostics) {
    std::lock_guard<std::mutex> lock(mutex_);
    // Entries of meshes that are gone are dropped when the store has doubled since the last sweep.
    if (kept_.size() >= 2 * afterSweep_ + 64) {
      std::erase_if(kept_, [](const auto& e) { return e.second.mesh.expired(); });
      afterSweep_ = kept_.size();
    }
    BuiltMesh& b = kept_[o.mesh.get()];
    b.mesh = o.mesh;
    b.cad = cad;
    b.options = options;
    b.built = WorldObject{};
    copyGeometry(b.built, o);
    b.built.info.proxyReason = o.info.proxyReason;
    b.built.info.buildSeconds = o.info.buildSeconds;
    b.diagnostics = std::move(diagnostics);
  }
  static void copyGeometry(WorldObject& to, const WorldObject& from) {
    to.mesh = from.mesh;
    to.bvh = from.bvh;
    to.geometry = from.geometry;
    to.bvhToMesh = from.bvhToMesh;
    to.patches = from.patches;
    to.nodePlane = from.nodePlane;
    to.nodeCylinder = from.nodeCylinder;
    to.nodeBox = from.nodeBox;
    to.localBounds = from.localBounds;
    to.info.proxy = from.info.proxy;
    to.info.triangles = from.info.triangles;
    to.info.planarPatches = from.info.planarPatches;
    to.info.cylindricalPatches = from.info.cylindricalPatches;
  }

 private:
  static bool same(const PatchOptions& a, const PatchOptions& b) {
    return a.distanceTolerance == b.distanceTolerance && a.angleTolerance == b.angleTolerance &&
           a.maxFacetTurn == b.maxFacetTurn && a.minFacets == b.minFacets && a.weldTolerance == b.weldTolerance;
  }
  std::mutex mutex_;
  std::unordered_map<const TriMesh*, BuiltMesh> kept_;
  std::size_t afterSweep_ = 0;
};

BuiltMeshes& builtMeshes() {
  static BuiltMeshes store;
  return store;
}

Eigen::AlignedBox3d transformedBox(const Eigen::AlignedBox3d& b, const Eigen::Isometry3d& tf) {
  Eigen::AlignedBox3d out;
  if (b.isEmpty()) return out;
  for (int i = 0; i < 8; ++i) out.extend(tf * b.corner(static_cast<Eigen::AlignedBox3d::CornerType>(i)));
  return out;
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
  // Each object's diagnostics in its own slot, appended in the objects' order at the end: the builds run
  // side by side and finish in any order.
  std::deque<Diagnostics> slots;
  // Meshes built here: on every core (building the hierarchies and patches was most of a world's
  // construction for a product of many parts), each distinct mesh once.
  struct Pending {
    WorldObject* o;
    const CadSolid* cad;
    Diagnostics* diags;
    Diagnostics found;
  };
  std::vector<Pending> pending;
  struct Copy {
    WorldObject* o;
    std::size_t from;  // in `pending`
    const CadSolid* cad;
    Diagnostics* diags;
  };
  std::vector<Copy> copies;
  // Parts with the same mesh (one mesh file used many times: bolts, nuts) share its hierarchy and
  // patches: built once. Found by a hash of the geometry and confirmed by comparing it. The value: a
  // built object, or (null) the pending build it waits for.
  std::multimap<std::uint64_t, std::pair<const WorldObject*, std::size_t>> built;
  const auto sameMesh = [](const TriMesh& a, const std::shared_ptr<const TriMesh>& b) {
    return &a == b.get() || (a.vertices == b->vertices && a.triangles == b->triangles);
  };
  auto setupMesh = [&](WorldObject& o, const std::shared_ptr<const TriMesh>& display, const CadSolid* cad, Diagnostics& diags) {
    o.info.displayTriangles = display ? display->triangleCount() : 0;
    o.deflection = cad ? cad->deflection : 0.0;
    if (!display) {
      warn(diags, Diagnostic::Severity::Error, displayName(o), "no-geometry", "a mesh", "none");
      o.info.proxy = ProxyKind::None;
      o.info.proxyReason = "no mesh";
      return;
    }
    if (auto simple = simplifiedFor(o.id)) {
      buildMesh(o, simple, options.patches, diags);
      if (o.bvh) {
        o.info.proxy = ProxyKind::SimplifiedMesh;
        // Two-sided sampled distance between the simplified and the full mesh.
        WorldObject full;
        full.id = o.id;
        full.info.name = o.info.name;
        Diagnostics ignore;
        buildMesh(full, display, options.patches, ignore, cad);
        double dev = full.bvh ? sampledDeviation(*simple, *full.bvh, 20000) : 0.0;
        if (full.bvh) dev = std::max(dev, sampledDeviation(*display, *o.bvh, 20000));
        o.info.deviation = dev;
        o.info.proxyReason = "simplified mesh, " + std::to_string(o.info.triangles) + " of " +
                             std::to_string(o.info.displayTriangles) + " triangles, deviation " + fmt(dev) + " m (sampled)";
        return;
      }
    }
    const std::uint64_t key = meshHash(*display);
    for (auto [it, end] = built.equal_range(key); it != end; ++it) {
      const auto [done, waitFor] = it->second;
      if (done && sameMesh(*done->mesh, display)) {
        BuiltMeshes::copyGeometry(o, *done);
        o.info.proxyReason = "full mesh, shared with " + displayName(*done);
        return;
      }
      if (!done && sameMesh(*pending[waitFor].o->mesh, display)) {
        copies.push_back({&o, waitFor, cad, &diags});
        o.mesh = display;
        return;
      }
    }
    if (builtMeshes().take(o, display, cad, options.patches, diags)) {
      built.emplace(key, std::pair{&o, std::size_t{0}});
      return;
    }
    o.mesh = display;
    built.emplace(key, std::pair{nullptr, pending.size()});
    pending.push_back({&o, cad, &diags, {}});
  };
  for (std::size_t i = 0; i < assembly.parts.size(); ++i) {
    const Part& p = assembly.parts[i];
    WorldObject& o = w.parts[i];
    o.id = ObjectId::part(i);
    o.info.id = o.id;
    o.info.name = p.name;
    o.pose = p.pose;
    o.com = p.mass.centerOfMass;
    setupMesh(o, p.mesh, p.cad.get(), slots.emplace_back());
  }
  for (std::size_t i = 0; i < assembly.environment.size(); ++i) {
    const EnvironmentObject& e = assembly.environment[i];
    WorldObject& o = w.environment[i];
    o.id = ObjectId::environment(i);
    o.info.id = o.id;
    o.info.name = e.name;
    o.pose = e.pose;
    o.info.displayTriangles = e.mesh ? e.mesh->triangleCount() : 0;
    Diagnostics& diags = slots.emplace_back();
    if (options.environmentPrimitives && !simplifiedFor(o.id) && e.mesh && tryPrimitive(o, e, diags)) continue;
    setupMesh(o, e.mesh, nullptr, diags);
  }
  // The largest first, so that no core is left with a large one at the end.
  std::vector<std::size_t> byWork(pending.size());
  for (std::size_t k = 0; k < byWork.size(); ++k) byWork[k] = k;
  std::sort(byWork.begin(), byWork.end(), [&](std::size_t x, std::size_t y) {
    return pending[x].o->mesh->triangles.size() > pending[y].o->mesh->triangles.size();
  });
  vaw::detail::onCores(byWork.size(), [&](std::size_t k, bool) {
    Pending& job = pending[byWork[k]];
    buildMesh(*job.o, job.o->mesh, options.patches, job.found, job.cad);
  });
  for (Pending& job : pending) {
    job.diags->insert(job.diags->end(), job.found.begin(), job.found.end());
    if (job.o->bvh) {
      job.o->info.proxy = ProxyKind::Mesh;
      job.o->info.proxyReason = "full mesh";
      builtMeshes().keep(*job.o, job.cad, options.patches, std::move(job.found));
    }
  }
  for (const Copy& c : copies) {
    const WorldObject& from = *pending[c.from].o;
    if (from.bvh) {
      BuiltMeshes::copyGeometry(*c.o, from);
      c.o->info.proxyReason = "full mesh, shared with " + displayName(from);
      continue;
    }
    // What the first could not build, this one reports for itself.
    Diagnostics found;
    buildMesh(*c.o, c.o->mesh, options.patches, found, c.cad);
    c.diags->insert(c.diags->end(), found.begin(), found.end());
    if (c.o->bvh) c.o->info.proxy = ProxyKind::Mesh;
  }
  for (Diagnostics& d : slots) w.diagnostics.insert(w.diagnostics.end(), d.begin(), d.end());
  w.makeBroadPhase();
  // Designed interferences, matched to the bore's cylinders once: the bore's span along the axis.
  for (const Constraint& c : assembly.constraints) {
    if (c.type != Constraint::Type::Insert || !c.found || c.found->fit == Constraint::Found::Fit::Clearance || !w.base) continue;
    const PartId partner = c.partner.value_or(*w.base);
    if (c.part >= w.parts.size() || partner >= w.parts.size()) continue;
    const bool partIsShaft = c.found->partRadius > c.found->partnerRadius;
    const PartId borePart = partIsShaft ? partner : c.part;
    const SurfacePatches* bp = patches(ObjectId::part(borePart));
    if (!bp) continue;
    DesignedFit f;
    f.axis = partIsShaft ? c.baseAxis : c.partAxis;
    f.axis.direction.normalize();
    f.boreRadius = std::min(c.found->partRadius, c.found->partnerRadius);
    f.shaftRadius = std::max(c.found->partRadius, c.found->partnerRadius);
    f.axialMin = std::numeric_limits<double>::infinity();
    f.axialMax = -f.axialMin;
    for (const int i : detail::cylindersOnAxis(*bp, f.axis, w.tol)) {
      const CylindricalPatch& cyl = bp->cylinders[static_cast<std::size_t>(i)];
      if (cyl.convex || std::abs(cyl.radius - f.boreRadius) > w.tol.radius) continue;
      for (const double t : {0.0, cyl.length}) {
        const double along = f.axis.direction.dot(cyl.point + t * cyl.direction - f.axis.point);
        f.axialMin = std::min(f.axialMin, along);
        f.axialMax = std::max(f.axialMax, along);
      }
    }
    if (!(f.axialMin <= f.axialMax)) continue;
    f.other = partIsShaft ? c.part : partner;
    f.bore = true;
    w.parts[borePart].designed.push_back(f);
    f.other = borePart;
    f.bore = false;
    w.parts[partIsShaft ? c.part : partner].designed.push_back(f);
  }
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
    o.nodeBox = from.nodeBox;
    o.pose = from.pose;
    o.geometryOffset = from.geometryOffset;
    o.localBounds = from.localBounds;
    o.boxHalf = from.boxHalf;
    o.com = from.com;
    o.designed = from.designed;
    o.deflection = from.deflection;
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

bool CollisionWorld::restOnEachOther(ObjectId a, ObjectId b) const {
  const WorldObject& A = impl_->get(a);
  const WorldObject& B = impl_->get(b);
  if (!A.bvh || !B.bvh || !A.nodeBox || !B.nodeBox || A.nodeBox->empty() || B.nodeBox->empty()) return false;
  // Each object's extent along a world direction, from its hierarchy's root box in its own frame.
  const auto extent = [](const WorldObject& o, const Eigen::Vector3d& n) {
    const Eigen::AlignedBox3d& box = (*o.nodeBox)[0];
    const Eigen::Vector3d local = o.pose.linear().transpose() * n;
    const double centre = n.dot(o.pose * box.center()), half = local.cwiseAbs().dot(0.5 * box.sizes());
    return std::pair{centre - half, centre + half};
  };
  const auto across = [&](const WorldObject& owner, const WorldObject& other, int k) {
    const PlanarPatch& p = owner.patches->planes[static_cast<std::size_t>(k)];
    const double room = impl_->tol.distance - p.residual;
    if (room < 0.0) return false;
    const Eigen::Vector3d n = (owner.pose.linear() * p.normal).normalized();
    const double level = n.dot(owner.pose * p.origin);
    const auto [lo, hi] = extent(owner, n);
    const auto [otherLo, otherHi] = extent(other, n);
    // The face points out of its owner: the owner below the plane, the other above, both reaching it.
    return std::abs(hi - level) <= room && std::abs(otherLo - level) <= room && lo < level && otherHi > level;
  };
  for (const int k : A.patches->largestPlanes)
    if (across(A, B, k)) return true;
  for (const int k : B.patches->largestPlanes)
    if (across(B, A, k)) return true;
  return false;
}

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
    for (int i = 0; i < 8; ++i)
      r = std::max(r, (o.localBounds.corner(static_cast<Eigen::AlignedBox3d::CornerType>(i)) - point).norm());
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
  std::sort(out.begin(), out.end(),
            [](const ObjectId& a, const ObjectId& b) { return a.kind != b.kind ? a.kind < b.kind : a.index < b.index; });
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

Eigen::Vector3d CollisionWorld::centreOfMass(PartId p) const { return impl_->get(ObjectId::part(p)).com; }

}  // namespace vaw::collision
