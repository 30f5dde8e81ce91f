#pragma once
// The collision world's insides, shared by the files that implement it (docs/collision.md): the object store
// (collision_world.cpp), the filtered pair queries (collision_query.cpp), the blocked and colliding checks
// (collision_blocked.cpp), ray casts (collision_ray.cpp) and the free motion of a support
// (collision_free_motion.cpp). Not installed: nothing outside core/src/collision includes it.
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <cmath>
#include <numbers>
#include <functional>
#include <limits>
#include <map>
#include <sstream>
#include <tuple>
#include <utility>

#include "fcl_includes.hpp"
#include "geometry2d.hpp"
#include "pair_geometry.hpp"
#include "vaw/collision/collision_world.hpp"

namespace vaw::collision {

using BV = fcl::OBBRSSd;
using Model = fcl::BVHModel<BV>;
using BaseNode = fcl::detail::MeshCollisionTraversalNodeOBBRSS<double>;
using pairgeom::Tri;

// A designed interference this part is in (a thread modelled at its tap drill, a press fit: the insert's
// Found::fit): the shaft's solid fills the band between the bore's radius and its own by design, and no
// triangle pair inside that band is a contact (docs/collision.md, "Designed interference").
struct DesignedFit {
  PartId other = 0;   // the part on the other side of the fit
  bool bore = false;  // this part holds the bore
  // In the bore part's frame: the axis, and the span along it (from axis.point) of the bore's faces on it.
  Axis axis;
  double axialMin = 0.0, axialMax = 0.0;
  double boreRadius = 0.0, shaftRadius = 0.0;  // m
};

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
  // Per BVH node: the box of its triangles along the mesh's own axes. Tighter than FCL's fitted boxes
  // along those axes, which most ways home follow (a plate's fitted box leans by a fraction of its 2 m
  // and reaches centimetres above its face).
  std::shared_ptr<const std::vector<Eigen::AlignedBox3d>> nodeBox;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d geometryOffset = Eigen::Isometry3d::Identity();  // object frame -> FCL geometry frame
  Eigen::AlignedBox3d localBounds;
  Eigen::Vector3d boxHalf = Eigen::Vector3d::Zero();  // Box proxies
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
  std::vector<DesignedFit> designed;  // parts only
  double deflection = 0.0;  // m, the CAD tessellation's chordal deflection (0 for a plain mesh)

  [[nodiscard]] Eigen::Isometry3d fclPose(const Eigen::Isometry3d& p) const { return p * geometryOffset; }
  // How far a triangle may lie inside the true surface: a cylinder's facets by its sagitta; a facet of any
  // other curved CAD face (a cone's, a fillet's) by the tessellation's chordal deflection, so that two such
  // faces in contact (a screw's head in its countersink) only touch.
  [[nodiscard]] double sagitta(int tri) const {
    const auto t = static_cast<std::size_t>(tri);
    const int c = patches->cylinderOf.empty() ? -1 : patches->cylinderOf[t];
    if (c >= 0) return patches->cylinders[static_cast<std::size_t>(c)].sagitta;
    return t < patches->curved.size() && patches->curved[t] ? deflection : 0.0;
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

namespace detail {
// A number with four significant digits, for messages.
std::string fmt(double v);

// The cylindrical patches whose axes lie on `axis` (unit direction) within the tolerances.
std::vector<int> cylindersOnAxis(const SurfacePatches& sp, const Axis& axis, const Tolerances& tol);

// What a pair query may skip: base BVH nodes below the support plane, and the support's fit pairs.
struct Cull {
  const std::vector<char>* bBelow = nullptr;
  const std::vector<std::pair<int, int>>* fit = nullptr;  // PairContext::fit
  double fitClearance = 0.0;
};
// The filtered query of object A at poseA against B at its pose (collision_query.cpp).
QueryResult runQuery(const Tolerances& tol, const WorldObject& A, const Eigen::Isometry3d& poseA, const WorldObject& B,
                     const QueryOptions& options, const Cull& cull);
}  // namespace detail

}  // namespace vaw::collision
