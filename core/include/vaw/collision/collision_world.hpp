#pragma once
// Collision checks for the workbench (docs/physics.md, "Collision checks on the base"; the paper's section 6), on FCL. FCL stays
// inside the implementation: nothing here names an FCL type.
//
// A CollisionWorld is built once from an Assembly: one bounding-volume hierarchy per part mesh (meshes are
// rigid), its surface patches, and a broad phase over all parts and environment objects. Per step only the
// parts that moved get setPose(); static and placed parts cost nothing. Queries run for one object against
// what its bounding box reaches. Objects are referred to by ObjectId (a part's PartId or an environment
// object's index), never by pointer. Poses are part frame -> world, SI units.
#include <Eigen/Geometry>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "vaw/assembly.hpp"
#include "vaw/collision/surface_patches.hpp"
#include "vaw/error.hpp"

namespace vaw::collision {

struct ObjectId {
  enum class Kind : std::uint8_t { Part, Environment };
  Kind kind = Kind::Part;
  std::size_t index = 0;  // PartId, or index into Assembly::environment

  static constexpr ObjectId part(PartId p) { return {Kind::Part, p}; }
  static constexpr ObjectId environment(std::size_t i) { return {Kind::Environment, i}; }
  friend constexpr bool operator==(const ObjectId&, const ObjectId&) = default;
};

// Filter modes of a mesh-mesh query (the paper's section 6).
enum class FilterMode {
  NoCare,        // every intersecting triangle pair
  KeepCoplanar,  // only pairs that are parallel and within Tolerances::distance (a gap counts)
  SkipCoplanar,  // every intersecting pair except parallel ones within Tolerances::distance
  SkipCoaxial,   // every intersecting pair except those of two equal-diameter coaxial cylinders (and a
                 // cylinder's end face against the other cylinder: a sleeve's end on its shaft)
};
std::string_view name(FilterMode m);

struct Tolerances {
  double distance = 1e-5;  // m: coplanar gap; touching; penetration below which a pair only touches
  double angle = 1e-3;     // rad: parallel normals, parallel axes
  // m: two cylinders have equal diameters (SKIP_COAXIAL); a bore smaller than its shaft by no more than
  // this still fits (with clearance 0), beyond it is interference.
  double radius = 5e-5;
};

// What an object collides as (its "collision proxy"), chosen per object and shown in the scene tree.
enum class ProxyKind { Mesh, SimplifiedMesh, Box, Sphere, Cylinder, None };
std::string_view name(ProxyKind k);

struct ObjectInfo {
  ObjectId id;
  std::string name;
  ProxyKind proxy = ProxyKind::Mesh;
  std::string proxyReason;          // why this proxy (shown with it)
  std::size_t triangles = 0;        // of the collision geometry (0 for a primitive)
  std::size_t displayTriangles = 0; // of the display mesh
  double deviation = 0.0;           // m: measured largest distance between proxy and display mesh
  double buildSeconds = 0.0;        // bounding-volume hierarchy and surface patches
  std::size_t planarPatches = 0;
  std::size_t cylindricalPatches = 0;
  // Parts: how each of its mate and insert constraints meets the base, for people (describeFit), e.g.
  // "insert: the part's bore (r = 15.05 mm) on the base's shaft (r = 15 mm), clearance 0.05 mm"; empty
  // for a part without constraints.
  std::string fit;
};

struct Contact {
  ObjectId a, b;
  int triangleA = -1, triangleB = -1;  // indices into each object's collision mesh; -1 for a primitive
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // world; FCL's, meaningless for exactly touching faces
  double penetration = 0.0;  // m: how far the two triangles pass through each other's planes; <= 0 touching
  double allowance = 0.0;    // m: penetration this pair may have and still only touch (distance + sagittas)
  bool coplanar = false;     // parallel within the angle tolerance and within the distance tolerance
  bool coaxial = false;      // both on cylinders of equal diameter on one axis (or one's end face on the other)
};

struct QueryOptions {
  FilterMode mode = FilterMode::NoCare;
  std::size_t maxContacts = 4096;
  bool dropTouching = false;  // drop pairs whose penetration is within their allowance (resting faces)
  bool stopAtFirst = false;   // a yes/no answer: stop at the first contact kept
  // Drop the pairs inside a designed interference (a thread modelled at its tap drill, a press fit: an
  // insert's Found::fit), as SKIP_COAXIAL always does: what is left of two overlapping parts is a clash.
  bool skipDesigned = false;
};

struct QueryResult {
  std::vector<Contact> contacts;
  std::size_t intersecting = 0;  // triangle pairs found before filtering
  std::size_t filtered = 0;      // removed by the filter mode or as touching only
  bool truncated = false;        // maxContacts reached
  std::size_t boundingVolumeTests = 0;  // node pairs tested in the hierarchies (the query's cost)
  std::size_t leafTests = 0;            // triangle pairs reached
};

struct WorldOptions {
  Tolerances tolerances;
  PatchOptions patches;
  // Environment objects made from a box, sphere or cylinder primitive collide as that exact shape
  // (measured against their mesh); otherwise as their mesh.
  bool environmentPrimitives = true;
  // Optional simplified collision meshes, per object: queries use them, the display keeps the full mesh;
  // their deviation from the full mesh is measured and reported.
  std::vector<std::pair<ObjectId, std::shared_ptr<const TriMesh>>> simplified;
};

struct SupportCache;  // defined by the implementation: what the checks precompute for one support

// How a part rests on the base, from one mate or insert constraint: the constraint surfaces matched once to
// the patches of both meshes. `problem` says why touching cannot be decided (then it is always false).
struct Support {
  enum class Kind { Plane, Axis };
  Kind kind = Kind::Plane;
  PartId part = 0;
  PartId base = 0;
  Plane partPlane{}, basePlane{};  // Plane: in each one's own frame, normals out of each solid
  double offset = 0.0;             // m, mate offset
  Axis partAxis{}, baseAxis{};     // Axis: in each one's own frame
  std::vector<int> partPatches;    // planar (Plane) or cylindrical (Axis) patch indices of the part
  std::vector<int> basePatches;    // of the base
  // Axis: the bore-and-shaft pairs of the fit (part cylinder, base cylinder), the tightest pairs on the
  // axis that are not interference, and their radial clearance, bore radius minus shaft radius (m, >= 0:
  // a bore smaller by no more than Tolerances::radius counts as 0). The part rests in its play on the
  // side gravity pulls it to; its axis may lie up to `clearance` off the base's.
  std::vector<std::pair<int, int>> fitPairs;
  double clearance = 0.0;
  double partRadius = 0.0, baseRadius = 0.0;  // m, the tightest pair's cylinders
  bool partIsBore = true;                     // a sleeve on a shaft; false: a pin in a hole
  std::string problem;
  // Precomputed once with the support (a few ms for a 250k-triangle base): which parts of the two
  // hierarchies the blocked check can skip while the part rests on the surface (docs/collision.md).
  std::shared_ptr<const SupportCache> cache;
};

struct TouchResult {
  bool touching = false;
  // Plane: signed distance (m) of the centre of mass's projection inside the support polygon (the convex
  // hull of the faces' overlap), negative outside. Axis: length (m) of axial overlap of the part's bore and
  // the base's cylinder (or shaft and bore), negative when apart. Touching iff margin >= -distance tol.
  double margin = 0.0;
  double separation = 0.0;   // m: plane gap (minus the mate offset) or distance between the axes
  double supportArea = 0.0;  // m^2 (Plane)
  std::vector<Eigen::Vector3d> supportPolygon;  // world (Plane)
  Eigen::Vector3d comProjection = Eigen::Vector3d::Zero();  // world (Plane)
  std::string reason;        // when not touching
};

// Around a part resting on its support, the motions of its reduced model that can meet nothing: along
// them the part is neither blocked nor loses touch (docs/collision.md, "Free motion"). Found from what the
// support precomputes (the base's faces near the part's path, the fit's spans, the support face's outline)
// and the boxes of the other objects the path reaches, without a mesh query, so the world need not sample
// the two checks along a step that stays inside it.
struct FreeMotion {
  // Axis: any slide along the base's axis by d in [axialMin, axialMax] (m, from the pose asked about),
  // with any turn about the part's own axis. Plane: any slide in the base's plane shorter than `radius`.
  // Zero when nothing is known free (the part is near an obstacle or an edge, or off its support).
  double axialMin = 0.0, axialMax = 0.0;
  double radius = 0.0;
  // What ends it there: the span of an obstacle's face (met face-on, the part is blocked within a tolerance
  // beyond; a span is a bound, so it may also be met later or passed), the end of the touch (lost within
  // two tolerances beyond), or a conservative bound. A search beyond an obstacle or the touch's end looks
  // first just beyond it. The plane's radius uses `atMax`.
  enum class Bound : std::uint8_t { Conservative, Obstacle, Touch };
  Bound atMin = Bound::Conservative, atMax = Bound::Conservative;
};

struct BlockResult {
  bool blocked = false;
  std::vector<Contact> contacts;  // the blocking pairs found (penetration beyond their allowance)
  std::optional<ObjectId> by;     // the first blocking object
  std::size_t boundingVolumeTests = 0;  // cost, summed over the objects tested
  std::size_t leafTests = 0;
};

// The constraint's surfaces matched to the patches of the part's and the base's meshes, without the
// blocked check's cache: what CollisionWorld::support starts from, usable without building hierarchies.
// Null patches (no mesh) give a Support with a problem.
Support matchSupport(const Constraint& constraint, PartId base, const SurfacePatches* partPatches,
                     const SurfacePatches* basePatches, const Tolerances& tolerances = {});
// One line for people: "insert: the part's bore (r = 15.05 mm) on the base's shaft (r = 15 mm), clearance
// 0.05 mm", "mate: 1 face of the part on 1 face of the base", or the constraint's problem.
std::string describeFit(const Support& support);

// Every constraint of an assembly matched and described (vaw-sim inspect): surface patches of the parts
// involved only, no hierarchy, so inspecting a large mesh costs no collision build.
struct ConstraintFit {
  std::size_t constraint = 0;  // index into Assembly::constraints
  Support support;
  std::string text;  // describeFit
};
std::vector<ConstraintFit> constraintFits(const Assembly& assembly, const Tolerances& tolerances = {});

class CollisionWorld {
 public:
  explicit CollisionWorld(const Assembly& assembly, const WorldOptions& options = {});
  ~CollisionWorld();
  CollisionWorld(CollisionWorld&&) noexcept;
  CollisionWorld& operator=(CollisionWorld&&) noexcept;
  CollisionWorld(const CollisionWorld&) = delete;
  CollisionWorld& operator=(const CollisionWorld&) = delete;

  // A world over the same geometry (hierarchies, patches, proxies: shared, never rebuilt) with its own
  // poses and broad phase, starting from this one's poses. Building a world costs hundreds of milliseconds
  // for a large assembly; an instance costs a copy of per-object indices. Geometry is only read by queries,
  // so instances may be used from different threads.
  [[nodiscard]] CollisionWorld instance() const;

  [[nodiscard]] std::size_t partCount() const;
  [[nodiscard]] std::size_t environmentCount() const;
  [[nodiscard]] std::optional<PartId> base() const;
  [[nodiscard]] const Tolerances& tolerances() const;
  // Warnings and errors found while building (bad meshes, rejected proxies), each naming the object.
  [[nodiscard]] const Diagnostics& diagnostics() const;
  [[nodiscard]] const ObjectInfo& info(ObjectId id) const;
  // Null for primitive proxies and objects without collision geometry.
  [[nodiscard]] const SurfacePatches* patches(ObjectId id) const;
  [[nodiscard]] const TriMesh* collisionMesh(ObjectId id) const;
  [[nodiscard]] std::vector<ObjectId> objects() const;

  // Moves one object; the broad phase is updated for it alone.
  void setPose(ObjectId id, const Eigen::Isometry3d& pose);
  [[nodiscard]] const Eigen::Isometry3d& pose(ObjectId id) const;
  // World box around the object's local bounding box at its pose (or at `pose`); empty without geometry.
  // Whether a and b lie wholly on either side of the plane of one of their largest flat faces, each reaching
  // it (within the distance tolerance, at their poses): a cover on a plate, a foot on a floor. Such a pair
  // can at most touch in that plane; docs/collision.md, "Separating planes".
  [[nodiscard]] bool restOnEachOther(ObjectId a, ObjectId b) const;
  [[nodiscard]] Eigen::AlignedBox3d worldBounds(ObjectId id) const;
  [[nodiscard]] Eigen::AlignedBox3d worldBounds(ObjectId id, const Eigen::Isometry3d& pose) const;
  // Largest distance of the object's collision geometry from a point / line in its own frame (m): the
  // speed bound of a rotation about that point or axis, per rad/s.
  [[nodiscard]] double maxRadius(ObjectId id, const Eigen::Vector3d& point) const;
  [[nodiscard]] double maxRadius(ObjectId id, const Axis& axis) const;

  // Objects whose bounding boxes overlap `box` (world), excluding `except` (broad phase).
  [[nodiscard]] std::vector<ObjectId> near(const Eigen::AlignedBox3d& box, std::optional<ObjectId> except = {}) const;

  // Triangle pairs between a and b under a filter mode; `poseA` overrides a's pose (b keeps its own).
  [[nodiscard]] QueryResult query(ObjectId a, ObjectId b, const QueryOptions& options = {}) const;
  [[nodiscard]] QueryResult query(ObjectId a, const Eigen::Isometry3d& poseA, ObjectId b, const QueryOptions& options = {}) const;
  // a against everything its bounding box reaches.
  [[nodiscard]] QueryResult queryAll(ObjectId a, const QueryOptions& options = {}) const;

  // The smallest distance between a and b at their poses and where it is: the nearest point of each, in
  // world coordinates. Distance 0 when they touch or intersect; infinite (points unset) when one has no
  // collision geometry.
  struct Nearest {
    double distance = std::numeric_limits<double>::infinity();
    Eigen::Vector3d onA = Eigen::Vector3d::Zero(), onB = Eigen::Vector3d::Zero();
    bool beyond = false;  // `distance` is `atMost`, a lower bound; the points are unset
  };
  // `near`: two points, one on each surface at their poses (the last step's nearest points carried along):
  // the answer is never farther than they are, and the search leaves out everything farther, which makes a
  // path's next step cost a fraction of the first. `atMost`: a caller that needs no distance from it on
  // gets any such distance back as `atMost`, marked `beyond`; the search then leaves out every pair of
  // nodes that far apart, so proving that two parts stay apart costs less than measuring how far.
  [[nodiscard]] Nearest nearest(ObjectId a, ObjectId b, const Nearest* near = nullptr,
                                double atMost = std::numeric_limits<double>::infinity()) const;
  // Smallest distance between a (at poseA) and b; 0 when they intersect.
  [[nodiscard]] double distance(ObjectId a, const Eigen::Isometry3d& poseA, ObjectId b) const;
  [[nodiscard]] double distance(ObjectId a, ObjectId b) const;
  // How far a (at poseA) can translate along `direction` before anything of b could block it, as a lower
  // bound: the smallest distance over the triangle pairs that could still meet on the way (docs/collision.md,
  // "Time of impact"). Left out: pairs whose shadows across the direction do not overlap, which never meet,
  // and pairs `mode` skips that stay skipped along the motion, and pairs the motion only takes apart (the
  // obstacle's triangle nowhere ahead of the mover's). Infinite when nothing can meet; distance() for
  // primitives. `atMost`: a caller that moves no farther needs no more; any distance from it on is
  // returned as `atMost`, which lets the search drop everything farther at once.
  [[nodiscard]] double distanceAlong(ObjectId a, const Eigen::Isometry3d& poseA, ObjectId b, FilterMode mode,
                                     const Eigen::Vector3d& direction,
                                     double atMost = std::numeric_limits<double>::infinity()) const;

  // How far a (at poseA) can translate along `direction` before one of its cylinders and an equal, coaxial
  // cylinder of b of the same kind (two shafts end to end, two bores) overlap along their axis by more than
  // the distance tolerance: the two solids then share volume, which their surfaces do not show (they cross
  // only at the rims, and the coaxial faces coincide). 0 when they overlap already; infinite when no such
  // pair comes to overlap. Only cylinders covering more than half a turn count, so that the two arcs must
  // share an angle.
  [[nodiscard]] double coaxialOverlapAlong(ObjectId a, const Eigen::Isometry3d& poseA, ObjectId b,
                                           const Eigen::Vector3d& direction) const;

  // The support of a part on the base from a mate or insert constraint (patches matched once), prepared
  // for blocked() and freeMotion() unless `prepared` is false.
  [[nodiscard]] Support support(const Constraint& constraint, bool prepared = true) const;
  // What blocked() and freeMotion() use, found once per support from the whole of its base's mesh (a plate
  // with hundreds of holes takes milliseconds): for a caller that prepares a support when it is first used.
  void prepare(Support& s) const;
  // Does the part still rest on (plane) or surround / sit in (axis) the constraint surface?
  [[nodiscard]] TouchResult touching(const Support& s) const;
  [[nodiscard]] TouchResult touching(const Support& s, const Eigen::Isometry3d& partPose) const;
  // Does any geometry other than the surface it moves on stop it: the base under SKIP_COPLANAR (plane,
  // tested with the part lifted by half the distance tolerance off the face it rests on, so the resting
  // faces are not even visited) or SKIP_COAXIAL (axis), everything else under NOCARE; pairs that only
  // touch (penetration within their allowance) never block.
  [[nodiscard]] BlockResult blocked(const Support& s, std::size_t maxContacts = 8) const;
  [[nodiscard]] BlockResult blocked(const Support& s, const Eigen::Isometry3d& partPose, std::size_t maxContacts = 8) const;
  // Anything at all in the way of an object at a pose (free flight): NOCARE against every reachable object;
  // touching-only pairs are ignored unless `countTouching`.
  [[nodiscard]] BlockResult colliding(ObjectId id, const Eigen::Isometry3d& pose, bool countTouching = false) const;
  // The motions free of events around the part at `partPose` on its support (FreeMotion). Costs a broad-phase
  // query and a pass over the support's few precomputed obstacles, no mesh query.
  [[nodiscard]] FreeMotion freeMotion(const Support& s, const Eigen::Isometry3d& partPose) const;

  // The first surface a ray from `origin` along the unit `direction` meets within `length` (m), skipping
  // `except`: where and what. Exact for meshes (the triangles found by the hierarchy are intersected with
  // the ray) and for box, sphere and cylinder proxies. For views (the drop line under a held part).
  struct RayHit {
    ObjectId object;
    Eigen::Vector3d point = Eigen::Vector3d::Zero();  // world
    double distance = 0.0;                            // m from origin
  };
  [[nodiscard]] std::optional<RayHit> castRay(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                                              double length, std::optional<ObjectId> except = {}) const;

  // Centre of mass of a part, part frame (from the assembly).
  [[nodiscard]] Eigen::Vector3d centreOfMass(PartId p) const;

 private:
  CollisionWorld();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vaw::collision
