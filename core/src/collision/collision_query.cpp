// Filtered pair queries (docs/collision.md, "Filter modes"): the mesh-mesh traversal with the filter in its
// leaf test, the primitives through FCL's own narrow phase, and distances.
#include "collision_world_impl.hpp"

namespace vaw::collision {

using detail::runQuery;

namespace {

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
  std::vector<signed char> looseCache; // the same for looselyCoaxial
  std::vector<signed char> rimOfA;     // per (plane of A, cylinder of B): a rim of that plane coaxial with it
  std::vector<signed char> rimOfB;     // per (cylinder of A, plane of B)
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // B frame -> A frame
  Eigen::Vector3d T = Eigen::Vector3d::Zero();
  bool stop = false;
  // Node culling for a support's blocked check (A = the part, B = the base); null when not in force.
  const std::vector<char>* bBelow = nullptr;
  // A support's fit with clearance (A = the part, B = the base): these bore-and-shaft pairs are coaxial
  // with their axes up to `fitClearance` apart (the part rests in its play) and radii that differ.
  const std::vector<std::pair<int, int>>* fit = nullptr;
  double fitClearance = 0.0;
  // The designed interferences between A and B (DesignedFit), in A's frame once the poses are set: a
  // triangle pair with the shaft's triangle inside the shaft's radius and the bore's outside the bore's,
  // within the bore's span, lies in the band the shaft fills by design and is no contact.
  struct Band {
    Eigen::Vector3d point, direction;
    double axialMin, axialMax, boreRadius, shaftRadius;
    bool boreIsA;
  };
  std::vector<Band> bands;

  // For the current B -> A transform (R, T).
  void findBands() {
    bands.clear();
    if (A->id.kind != ObjectId::Kind::Part || B->id.kind != ObjectId::Kind::Part) return;
    for (const DesignedFit& f : A->designed) {
      if (f.other != B->id.index) continue;
      // The axis is in the bore's part frame; triangles are in each mesh's model frame.
      const WorldObject& bore = f.bore ? *A : *B;
      Eigen::Vector3d point = bore.geometryOffset.inverse() * f.axis.point;
      Eigen::Vector3d direction = bore.geometryOffset.linear().transpose() * f.axis.direction;
      if (!f.bore) {
        point = R * point + T;
        direction = R * direction;
      }
      bands.push_back({point, direction.normalized(), f.axialMin, f.axialMax, f.boreRadius, f.shaftRadius, f.bore});
    }
  }

  bool inDesignedBand(const Tri& p, const Tri& q) const {
    const double slack = tol.distance + tol.radius;
    for (const Band& b : bands) {
      const Tri& shaft = b.boreIsA ? q : p;
      const Tri& bore = b.boreIsA ? p : q;
      bool inside = true;
      for (const Eigen::Vector3d& v : shaft) {
        const Eigen::Vector3d rel = v - b.point;
        inside = inside && (rel - b.direction * b.direction.dot(rel)).norm() <= b.shaftRadius + slack;
      }
      for (const Eigen::Vector3d& v : bore) {
        const Eigen::Vector3d rel = v - b.point;
        const double along = b.direction.dot(rel);
        inside = inside && (rel - b.direction * along).norm() >= b.boreRadius - slack && along >= b.axialMin - b.shaftRadius - slack &&
                 along <= b.axialMax + b.shaftRadius + slack;
      }
      if (inside) return true;
    }
    return false;
  }

  // Every triangle pair of node b1 (of A) and node b2 (of B) would be dropped by the mode.
  bool skipsWhole(int b1, int b2) {
    if (mode == FilterMode::SkipCoplanar || (opt.dropTouching && mode != FilterMode::KeepCoplanar)) {
      const int pa = A->nodePlane[static_cast<std::size_t>(b1)], pb = B->nodePlane[static_cast<std::size_t>(b2)];
      if (pa >= 0 && pb >= 0 && planesCoincide(pa, pb)) return true;
    }
    const int ca = A->nodeCylinder[static_cast<std::size_t>(b1)], cb = B->nodeCylinder[static_cast<std::size_t>(b2)];
    if (ca >= 0 && cb >= 0 && mode != FilterMode::KeepCoplanar && looselyCoaxial(ca, cb)) return true;
    if (mode == FilterMode::SkipCoaxial) {
      if (ca >= 0 && cb >= 0 && cylindersCoaxial(ca, cb)) return true;
      if (rimAgainstCylinder(A->nodePlane[static_cast<std::size_t>(b1)], cb, ca, B->nodePlane[static_cast<std::size_t>(b2)])) return true;
    }
    return false;
  }

  // An end face of one cylinder (planar patch pa of A, or pb of B) against the other's equal, coaxial
  // cylinder of the opposite kind (a sleeve's end face on its shaft, a shaft's cap in its bore). A plate's
  // face is the end face of every hole in it: the answer is kept per plane and cylinder, so that the
  // hundreds of holes of a large base are looked through once per query, not at every node pair.
  bool rimAgainstCylinder(int pa, int cb, int ca, int pb) {
    if (pa >= 0 && cb >= 0 &&
        anyRimCoaxial(rimOfA[static_cast<std::size_t>(pa) * B->patches->cylinders.size() + static_cast<std::size_t>(cb)],
                      A->patches->planes[static_cast<std::size_t>(pa)].rimOf, true, cb))
      return true;
    return ca >= 0 && pb >= 0 &&
           anyRimCoaxial(rimOfB[static_cast<std::size_t>(ca) * B->patches->planes.size() + static_cast<std::size_t>(pb)],
                         B->patches->planes[static_cast<std::size_t>(pb)].rimOf, false, ca);
  }

  // Whether one of `rims` (cylinders of A when `rimsOfA`, else of B) is of the opposite kind to, and coaxial
  // with, the other side's cylinder `other`; `known` keeps the answer (-1 not yet asked).
  bool anyRimCoaxial(signed char& known, const std::vector<int>& rims, bool rimsOfA, int other) {
    if (known < 0) {
      known = 0;
      for (const int rim : rims) {
        const int ca = rimsOfA ? rim : other, cb = rimsOfA ? other : rim;
        if (A->patches->cylinders[static_cast<std::size_t>(ca)].convex != B->patches->cylinders[static_cast<std::size_t>(cb)].convex &&
            cylindersCoaxial(ca, cb)) {
          known = 1;
          break;
        }
      }
    }
    return known == 1;
  }

  // For a new pair of poses: nothing known yet.
  void forget() {
    coaxCache.assign(A->patches->cylinders.size() * B->patches->cylinders.size(), -1);
    looseCache.assign(coaxCache.size(), -1);
    rimOfA.assign(A->patches->planes.size() * B->patches->cylinders.size(), -1);
    rimOfB.assign(A->patches->cylinders.size() * B->patches->planes.size(), -1);
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

  // Planes across which a pair can only touch, never cross (docs/collision.md, "Separating planes"): large
  // flat faces where the two parts rest on each other (a bracket's foot on a plate's top), in A's frame.
  // Two nodes or triangles wholly on opposite sides of one (within the distance tolerance) can meet only in
  // that plane: the walls of a bracket's holes above a plate and those of the plate's holes under it. In a
  // sweep only the planes the motion lies in, which stay separating all along.
  struct Separator {
    Eigen::Vector3d normal, origin;      // in A's frame
    Eigen::Vector3d normalB, originB;    // the same plane in B's frame
    Eigen::Vector3d absA, absB;          // |normal| per axis in either frame, for boxes along the frame's axes
    double room;
  };
  std::vector<Separator> separators;
  void findSeparators(const Eigen::Vector3d* dir, double sinAngle) {
    separators.clear();
    // Only planes where the two rest on each other: one part's large face lies in one of the other's, or
    // the two parts lie on either side of the plane, each reaching it. Any other plane would cost every
    // node pair a test and separate little.
    const Eigen::AlignedBox3d& boxA = (*A->nodeBox)[0];
    const Eigen::AlignedBox3d& boxB = (*B->nodeBox)[0];
    const auto inPlane = [&](const PlanarPatch& other, const Eigen::Vector3d& normal, const Eigen::Vector3d& origin, double room) {
      return std::abs(normal.dot(other.normal)) >= cosAngle && std::abs(normal.dot(other.origin - origin)) <= room;
    };
    const auto add = [&](const PlanarPatch& p, const Eigen::Vector3d& normal, const Eigen::Vector3d& origin, bool ofA) {
      const double room = tol.distance - p.residual;
      if (room < 0.0 || (dir && std::abs(normal.dot(*dir)) > sinAngle)) return;
      Separator s{normal, origin, R.transpose() * normal, R.transpose() * (origin - T), normal.cwiseAbs(), Eigen::Vector3d::Zero(), room};
      s.absB = s.normalB.cwiseAbs();
      const double da = s.normal.dot(boxA.center() - s.origin), ra = s.absA.dot(0.5 * boxA.sizes());
      const double db = s.normalB.dot(boxB.center() - s.originB), rb = s.absB.dot(0.5 * boxB.sizes());
      // Each box's side facing the other lies in the plane.
      const auto reaches = [&](double d, double r, double side) { return std::abs(d + side * r) <= room; };
      bool keep = (reaches(da, ra, 1.0) && reaches(db, rb, -1.0)) || (reaches(da, ra, -1.0) && reaches(db, rb, 1.0));
      // The other part's largest faces, each in its own frame.
      const std::vector<int>& others = ofA ? B->patches->largestPlanes : A->patches->largestPlanes;
      for (std::size_t k = 0; !keep && k < others.size(); ++k) {
        const PlanarPatch& q = (ofA ? B : A)->patches->planes[static_cast<std::size_t>(others[k])];
        const double both = tol.distance - std::max(p.residual, q.residual);
        keep = ofA ? inPlane(q, s.normalB, s.originB, both) : inPlane(q, s.normal, s.origin, both);
      }
      for (const Separator& t : separators)
        if (keep && std::abs(t.normal.dot(s.normal)) >= cosAngle && std::abs(t.normal.dot(s.origin - t.origin)) <= room) keep = false;
      if (keep) separators.push_back(s);
    };
    for (const int k : A->patches->largestPlanes) {
      const PlanarPatch& p = A->patches->planes[static_cast<std::size_t>(k)];
      add(p, p.normal, p.origin, true);
    }
    for (const int k : B->patches->largestPlanes) {
      const PlanarPatch& p = B->patches->planes[static_cast<std::size_t>(k)];
      add(p, R * p.normal, R * p.origin + T, false);
    }
  }
  static bool apartAcross(const Separator& s, double da, double ra, double db, double rb) {
    return (da + ra <= s.room && db - rb >= -s.room) || (da - ra >= -s.room && db + rb <= s.room);
  }
  // Two hierarchy nodes: by the boxes along the meshes' own axes (tight for a large flat part, whose fitted
  // boxes lean off its faces), else by FCL's fitted boxes (each in its mesh's frame).
  bool separated(int b1, const fcl::OBBd& a, int b2, const fcl::OBBd& b) const {
    if (separators.empty()) return false;
    const Eigen::AlignedBox3d& x1 = (*A->nodeBox)[static_cast<std::size_t>(b1)];
    const Eigen::AlignedBox3d& x2 = (*B->nodeBox)[static_cast<std::size_t>(b2)];
    const Eigen::Vector3d c1 = x1.center(), h1 = 0.5 * x1.sizes(), c2 = x2.center(), h2 = 0.5 * x2.sizes();
    for (const Separator& s : separators) {
      if (apartAcross(s, s.normal.dot(c1 - s.origin), s.absA.dot(h1), s.normalB.dot(c2 - s.originB), s.absB.dot(h2))) return true;
      const Eigen::Vector3d na = a.axis.transpose() * s.normal, nb = b.axis.transpose() * s.normalB;
      if (apartAcross(s, s.normal.dot(a.To - s.origin), na.cwiseAbs().dot(a.extent), s.normalB.dot(b.To - s.originB),
                      nb.cwiseAbs().dot(b.extent)))
        return true;
    }
    return false;
  }
  bool separated(const Tri& p, const Tri& q) const {
    for (const Separator& s : separators) {
      // A triangle's extent along the normal as a centre and a half width, as a box's.
      const auto side = [&](const Tri& t) {
        const double d0 = s.normal.dot(t[0] - s.origin), d1 = s.normal.dot(t[1] - s.origin), d2 = s.normal.dot(t[2] - s.origin);
        const double lo = std::min({d0, d1, d2}), hi = std::max({d0, d1, d2});
        return std::pair{0.5 * (lo + hi), 0.5 * (hi - lo)};
      };
      const auto [dp, rp] = side(p);
      const auto [dq, rq] = side(q);
      if (apartAcross(s, dp, rp, dq, rq)) return true;
    }
    return false;
  }

  bool coaxial(int ta, int tb) {
    const int ca = A->patches->cylinderOf[static_cast<std::size_t>(ta)];
    const int cb = B->patches->cylinderOf[static_cast<std::size_t>(tb)];
    if (ca >= 0 && cb >= 0) return cylindersCoaxial(ca, cb);
    return rimAgainstCylinder(A->patches->planeOf[static_cast<std::size_t>(ta)], cb, ca, B->patches->planeOf[static_cast<std::size_t>(tb)]);
  }

  // A shaft inside a looser bore on (nearly) its axis, the shaft's whole radius and the axes' offset short
  // of the bore's facets (which lie up to its sagitta inside the true bore) by more than the distance
  // tolerance: no facet of one meets a facet of the other, and none will while either moves along the axis
  // (a bolt in its clearance hole). Either part may be the shaft.
  bool looselyCoaxial(int ca, int cb) {
    const std::size_t key = static_cast<std::size_t>(ca) * B->patches->cylinders.size() + static_cast<std::size_t>(cb);
    if (looseCache[key] >= 0) return looseCache[key] == 1;
    const CylindricalPatch& a = A->patches->cylinders[static_cast<std::size_t>(ca)];
    const CylindricalPatch& b = B->patches->cylinders[static_cast<std::size_t>(cb)];
    bool yes = false;
    if (a.convex != b.convex && std::abs(a.direction.dot(R * b.direction)) >= cosAngle) {
      Eigen::Vector3d off = R * b.point + T - a.point;
      off -= a.direction * a.direction.dot(off);
      const CylindricalPatch& shaft = a.convex ? a : b;
      const CylindricalPatch& bore = a.convex ? b : a;
      yes = off.norm() + shaft.radius < bore.radius - bore.sagitta - tol.distance;
    }
    looseCache[key] = yes ? 1 : 0;
    return yes;
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
      const bool designed = !bands.empty() && (mode == FilterMode::SkipCoaxial || opt.skipDesigned) && inDesignedBand(p, q);
      const bool skip = (mode == FilterMode::SkipCoplanar && c.coplanar) || (mode == FilterMode::SkipCoaxial && c.coaxial) || designed;
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
    if (ctx->separated(p, q)) {
      ++ctx->out->filtered;
      return;
    }
    ctx->record(i1, i2, p, q, keepCoplanar);
  }
  bool canStop() const override { return ctx->stop; }
  // KEEP_COPLANAR: bounding volumes within the distance tolerance count as overlapping (an inflated test).
  bool BVTesting(int b1, int b2) const override {
    ++ctx->out->boundingVolumeTests;
    if (ctx->bBelow && (*ctx->bBelow)[static_cast<std::size_t>(b2)]) return true;
    if (ctx->skipsWhole(b1, b2)) return true;
    if (ctx->separated(b1, this->model1->getBV(b1).bv.obb, b2, this->model2->getBV(b2).bv.obb)) return true;
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
  ctx.forget();
  ctx.findBands();
  // Where touching is no contact, a pair that can only touch is left out.
  if (ctx.opt.dropTouching && ctx.mode != FilterMode::KeepCoplanar) ctx.findSeparators(nullptr, 0.0);
  node.ctx = &ctx;
  node.keepCoplanar = ctx.mode == FilterMode::KeepCoplanar;
  fcl::detail::collide(&node, nullptr);
}

// The distance that bounds how far a part can translate along a direction before a pair could block it
// (CollisionWorld::distanceAlong): FCL's mesh distance traversal with the leaf test leaving out the pairs
// that can never block that translation. Two triangles whose shadows on the plane across the direction do
// not overlap never meet while one translates along it (a shaft's facets and a looser bore's, the rim of a
// hole and the shaft through it); pairs the filter skips (equal coaxial cylinders along their axis, a rim
// on its coaxial cylinder, coincident planes while the motion stays in them) stay skipped all along.
class SweepDistanceNode : public fcl::detail::MeshDistanceTraversalNodeOBBRSS<double> {
 public:
  PairContext* ctx = nullptr;
  Eigen::Vector3d dir = Eigen::Vector3d::UnitZ();  // the motion, unit, in A's frame
  Eigen::Vector3d e1 = Eigen::Vector3d::UnitX(), e2 = Eigen::Vector3d::UnitY();
  double sinAngle = 0.0, cosAngle = 1.0, margin = 0.0;

  void preprocess() override {}
  void postprocess() override {}

  // Two bounding volumes whose shadows across the motion are apart hold no pair that can meet: pruned
  // whole, which keeps the traversal from visiting every pair of a shaft and its bore.
  double BVTesting(int b1, int b2) const override {
    if (apartAlongAxes(b1, b2)) return std::numeric_limits<double>::max();
    const fcl::OBBd& o1 = this->model1->getBV(b1).bv.obb;
    const fcl::OBBd& o2 = this->model2->getBV(b2).bv.obb;
    const Eigen::Vector3d c1 = o1.To, c2 = this->tf * o2.To;
    const Eigen::Matrix3d axes2 = this->tf.linear() * o2.axis;
    Eigen::Vector3d across = c2 - c1;
    across -= dir * dir.dot(across);
    const auto apart = [&](const Eigen::Vector3d& u) {
      double r = 0.0;
      for (int k = 0; k < 3; ++k) r += o1.extent[k] * std::abs(o1.axis.col(k).dot(u)) + o2.extent[k] * std::abs(axes2.col(k).dot(u));
      return std::abs((c2 - c1).dot(u)) > r + margin;
    };
    if (apart(e1) || apart(e2) || (across.norm() > 1e-12 && apart(across.normalized()))) return std::numeric_limits<double>::max();
    // Behind the mover: everything of the obstacle's volume lies no farther along the motion than the
    // mover's rearmost point (within the margin), so the motion only takes them apart (a bolt's head
    // leaving the bracket it sat on, a nut leaving the plate).
    double r = 0.0;
    for (int k = 0; k < 3; ++k) r += o1.extent[k] * std::abs(o1.axis.col(k).dot(dir)) + o2.extent[k] * std::abs(axes2.col(k).dot(dir));
    if ((c2 - c1).dot(dir) + r <= margin) return std::numeric_limits<double>::max();
    // Whole nodes the filter drops (a shank's facets in the plate's bore, both all on one cylinder).
    if (filtered(A().nodePlane[static_cast<std::size_t>(b1)], B().nodePlane[static_cast<std::size_t>(b2)],
                 A().nodeCylinder[static_cast<std::size_t>(b1)], B().nodeCylinder[static_cast<std::size_t>(b2)]))
      return std::numeric_limits<double>::max();
    if (ctx->separated(b1, o1, b2, o2)) return std::numeric_limits<double>::max();
    return fcl::detail::MeshDistanceTraversalNodeOBBRSS<double>::BVTesting(b1, b2);
  }

  void leafTesting(int b1, int b2) const override {
    const int i1 = this->model1->getBV(b1).primitiveId();
    const int i2 = this->model2->getBV(b2).primitiveId();
    const fcl::Triangle& t1 = this->tri_indices1[i1];
    const fcl::Triangle& t2 = this->tri_indices2[i2];
    const Tri p{this->vertices1[t1[0]], this->vertices1[t1[1]], this->vertices1[t1[2]]};
    const Tri q{this->tf * this->vertices2[t2[0]], this->tf * this->vertices2[t2[1]], this->tf * this->vertices2[t2[2]]};
    const int ta = A().bvhToMesh[static_cast<std::size_t>(i1)], tb = B().bvhToMesh[static_cast<std::size_t>(i2)];
    if (behind(p, q) || neverMeet(p, q) || (ctx->mode == FilterMode::SkipCoaxial && ctx->inDesignedBand(p, q)) ||
        filtered(A().patches->planeOf[static_cast<std::size_t>(ta)], B().patches->planeOf[static_cast<std::size_t>(tb)],
                 A().patches->cylinderOf[static_cast<std::size_t>(ta)], B().patches->cylinderOf[static_cast<std::size_t>(tb)]) ||
        ctx->separated(p, q))
      return;
    fcl::Vector3d P, Q;
    const double d = fcl::detail::TriangleDistance<double>::triDistance(p[0], p[1], p[2], q[0], q[1], q[2], P, Q);
    if (d < this->result->min_distance) this->result->update(d, this->model1, this->model2, i1, i2);
  }

  // The motion and the two shadow axes in B's frame (set with the pose).
  Eigen::Matrix3d inB = Eigen::Matrix3d::Identity();

 private:
  // The same two tests (shadows apart, obstacle behind) on the nodes' boxes along the meshes' own axes.
  bool apartAlongAxes(int b1, int b2) const {
    const Eigen::AlignedBox3d& x1 = (*A().nodeBox)[static_cast<std::size_t>(b1)];
    const Eigen::AlignedBox3d& x2 = (*B().nodeBox)[static_cast<std::size_t>(b2)];
    const Eigen::Vector3d h1 = 0.5 * x1.sizes(), h2 = 0.5 * x2.sizes();
    const Eigen::Vector3d gap = this->tf * x2.center() - x1.center();
    const auto reach = [&](const Eigen::Vector3d& u, int k) { return h1.dot(u.cwiseAbs()) + h2.dot(inB.col(k).cwiseAbs()); };
    if (std::abs(gap.dot(e1)) > reach(e1, 1) + margin || std::abs(gap.dot(e2)) > reach(e2, 2) + margin) return true;
    return gap.dot(dir) + reach(dir, 0) <= margin;
  }

  // The obstacle's triangle nowhere ahead of the mover's along the motion: they only move apart.
  bool behind(const Tri& p, const Tri& q) const {
    const double pMin = std::min({p[0].dot(dir), p[1].dot(dir), p[2].dot(dir)});
    const double qMax = std::max({q[0].dot(dir), q[1].dot(dir), q[2].dot(dir)});
    return qMax <= pMin + margin;
  }

  // Separated shadows: some edge normal of either projected triangle separates them by more than the margin.
  bool neverMeet(const Tri& p, const Tri& q) const {
    std::array<Eigen::Vector2d, 3> a, b;
    for (int k = 0; k < 3; ++k) {
      a[static_cast<std::size_t>(k)] = {p[static_cast<std::size_t>(k)].dot(e1), p[static_cast<std::size_t>(k)].dot(e2)};
      b[static_cast<std::size_t>(k)] = {q[static_cast<std::size_t>(k)].dot(e1), q[static_cast<std::size_t>(k)].dot(e2)};
    }
    const auto separates = [&](const Eigen::Vector2d& edge) {
      const Eigen::Vector2d n(-edge.y(), edge.x());
      const double len = n.norm();
      if (len < 1e-15) return false;
      double aMin = 1e300, aMax = -1e300, bMin = 1e300, bMax = -1e300;
      for (const auto& v : a) {
        aMin = std::min(aMin, n.dot(v) / len);
        aMax = std::max(aMax, n.dot(v) / len);
      }
      for (const auto& v : b) {
        bMin = std::min(bMin, n.dot(v) / len);
        bMax = std::max(bMax, n.dot(v) / len);
      }
      return aMax + margin < bMin || bMax + margin < aMin;
    };
    for (int k = 0; k < 3; ++k) {
      if (separates(a[static_cast<std::size_t>((k + 1) % 3)] - a[static_cast<std::size_t>(k)])) return true;
      if (separates(b[static_cast<std::size_t>((k + 1) % 3)] - b[static_cast<std::size_t>(k)])) return true;
    }
    return false;
  }

  [[nodiscard]] const WorldObject& A() const { return *ctx->A; }
  [[nodiscard]] const WorldObject& B() const { return *ctx->B; }

  // Whether the filter drops a pair of triangles, or of hierarchy nodes, on these planar and cylindrical
  // patches (-1: none, or not all on one).
  bool filtered(int planeA, int planeB, int ca, int cb) const {
    const SurfacePatches& pa = *ctx->A->patches;
    const SurfacePatches& pb = *ctx->B->patches;
    // Coincident planes stay coincident while the motion lies in them (the collision query drops them as
    // touching).
    if (planeA >= 0 && planeB >= 0 && std::abs(pa.planes[static_cast<std::size_t>(planeA)].normal.dot(dir)) <= sinAngle &&
        ctx->planesCoincide(planeA, planeB))
      return true;
    // A shaft moving along the axis of a looser bore round it never meets it.
    if (ca >= 0 && cb >= 0 && std::abs(pa.cylinders[static_cast<std::size_t>(ca)].direction.dot(dir)) >= cosAngle && ctx->looselyCoaxial(ca, cb))
      return true;
    if (ctx->mode != FilterMode::SkipCoaxial) return false;
    // Along the common axis only: moved sideways, coaxial cylinders stop being coaxial.
    const auto alongA = [&](int c) { return std::abs(pa.cylinders[static_cast<std::size_t>(c)].direction.dot(dir)) >= cosAngle; };
    const auto alongB = [&](int c) { return std::abs((ctx->R * pb.cylinders[static_cast<std::size_t>(c)].direction).dot(dir)) >= cosAngle; };
    if (ca >= 0 && cb >= 0) return alongA(ca) && ctx->cylindersCoaxial(ca, cb);
    if (cb >= 0 && planeA >= 0 && alongB(cb)) return ctx->rimAgainstCylinder(planeA, cb, -1, -1);
    if (ca >= 0 && planeB >= 0 && alongA(ca)) return ctx->rimAgainstCylinder(-1, -1, ca, planeB);
    return false;
  }
};

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


QueryResult CollisionWorld::query(ObjectId a, ObjectId b, const QueryOptions& options) const {
  return query(a, impl_->get(a).pose, b, options);
}

QueryResult CollisionWorld::query(ObjectId a, const Eigen::Isometry3d& poseA, ObjectId b, const QueryOptions& options) const {
  if (a == b) return {};
  return runQuery(impl_->tol, impl_->get(a), poseA, impl_->get(b), options, {});
}

namespace detail {
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
}  // namespace detail

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

CollisionWorld::Nearest CollisionWorld::nearest(ObjectId a, ObjectId b, const Nearest* near, double atMost) const {
  const WorldObject& A = impl_->get(a);
  const WorldObject& B = impl_->get(b);
  Nearest n;
  if (!A.geometry || !B.geometry) return n;
  fcl::DistanceRequestd req;
  req.enable_nearest_points = true;
  fcl::DistanceResultd res;
  // FCL keeps what the result holds and prunes every pair of nodes no closer (its traversal's stop test):
  // seeded a hair above the known pair, the search finds the true pair and only looks near it.
  double seeded = std::numeric_limits<double>::infinity();
  if (near) seeded = (near->onA - near->onB).norm() * (1.0 + 1e-9) + 1e-12;
  const bool bounded = atMost < seeded;
  if (bounded) seeded = atMost;
  if (std::isfinite(seeded)) res.min_distance = seeded;
  fcl::distance(A.geometry.get(), A.fclPose(A.pose), B.geometry.get(), B.fclPose(B.pose), req, res);
  if (bounded && res.min_distance >= seeded) {
    n.distance = atMost;
    n.beyond = true;
    return n;
  }
  if (near && res.min_distance >= seeded) {
    n.distance = (near->onA - near->onB).norm();
    n.onA = near->onA;
    n.onB = near->onB;
    return n;
  }
  n.distance = std::max(0.0, res.min_distance);
  // FCL (0.6 on) gives the nearest points in the world frame.
  n.onA = res.nearest_points[0];
  n.onB = res.nearest_points[1];
  return n;
}

double CollisionWorld::distance(ObjectId a, const Eigen::Isometry3d& poseA, ObjectId b) const {
  const WorldObject& A = impl_->get(a);
  const WorldObject& B = impl_->get(b);
  if (!A.geometry || !B.geometry) return std::numeric_limits<double>::infinity();
  fcl::DistanceRequestd req;
  fcl::DistanceResultd res;
  fcl::distance(A.geometry.get(), A.fclPose(poseA), B.geometry.get(), B.fclPose(B.pose), req, res);
  return std::max(0.0, res.min_distance);
}

double CollisionWorld::distanceAlong(ObjectId a, const Eigen::Isometry3d& poseA, ObjectId b, FilterMode mode,
                                     const Eigen::Vector3d& direction, double atMost) const {
  const WorldObject& A = impl_->get(a);
  const WorldObject& B = impl_->get(b);
  if (!A.bvh || !B.bvh || !(direction.norm() > 0.0)) return distance(a, poseA, b);
  QueryResult unused;
  PairContext ctx;
  ctx.A = &A;
  ctx.B = &B;
  ctx.mode = mode;
  ctx.tol = impl_->tol;
  ctx.out = &unused;
  SweepDistanceNode node;
  fcl::DistanceRequestd req;
  fcl::DistanceResultd res;
  const fcl::Transform3d tf1 = A.fclPose(poseA), tf2 = B.fclPose(B.pose);
  if (!fcl::detail::initialize(static_cast<fcl::detail::MeshDistanceTraversalNodeOBBRSS<double>&>(node), *A.bvh, tf1, *B.bvh, tf2,
                               req, res))
    return distance(a, poseA, b);
  ctx.R = node.tf.linear();
  ctx.T = node.tf.translation();
  ctx.cosAngle = std::cos(ctx.tol.angle);
  ctx.forget();
  ctx.findBands();
  node.ctx = &ctx;
  node.dir = (tf1.linear().transpose() * direction).normalized();
  node.e1 = node.dir.unitOrthogonal();
  node.e2 = node.dir.cross(node.e1);
  node.inB << node.tf.linear().transpose() * node.dir, node.tf.linear().transpose() * node.e1, node.tf.linear().transpose() * node.e2;
  node.cosAngle = ctx.cosAngle;
  node.sinAngle = std::sin(ctx.tol.angle);
  ctx.findSeparators(&node.dir, node.sinAngle);
  // Shadows closer than this count as overlapping: rounding, and the two tessellations' sagittas.
  node.margin = ctx.tol.distance;
  // FCL's traversal prunes every pair of volumes no nearer than the best distance so far: starting from
  // the cap prunes what lies beyond it from the first step.
  const bool capped = std::isfinite(atMost);
  res.min_distance = capped ? std::max(0.0, atMost) : std::numeric_limits<double>::max();
  fcl::detail::distance(&node, nullptr, 2);
  if (!capped && res.min_distance >= std::numeric_limits<double>::max()) return std::numeric_limits<double>::infinity();
  return std::max(0.0, res.min_distance);
}

double CollisionWorld::coaxialOverlapAlong(ObjectId a, const Eigen::Isometry3d& poseA, ObjectId b,
                                            const Eigen::Vector3d& direction) const {
  const WorldObject& A = impl_->get(a);
  const WorldObject& B = impl_->get(b);
  double first = std::numeric_limits<double>::infinity();
  if (!A.patches || !B.patches || !(direction.norm() > 0.0)) return first;
  const Tolerances& tol = impl_->tol;
  const Eigen::Vector3d dir = direction.normalized();
  const Eigen::Isometry3d tfA = A.fclPose(poseA), tfB = B.fclPose(B.pose);
  const double cosAngle = std::cos(tol.angle);
  for (const CylindricalPatch& ca : A.patches->cylinders) {
    if (ca.coverage <= std::numbers::pi) continue;
    const Eigen::Vector3d u = tfA.linear() * ca.direction;
    const double k = u.dot(dir);  // axial travel per unit of motion
    if (std::abs(k) < cosAngle) continue;  // moved off its axis it stops being coaxial
    const Eigen::Vector3d pa = tfA * ca.point;
    for (const CylindricalPatch& cb : B.patches->cylinders) {
      if (cb.convex != ca.convex || cb.coverage <= std::numbers::pi || std::abs(ca.radius - cb.radius) > tol.radius) continue;
      const Eigen::Vector3d v = tfB.linear() * cb.direction;
      if (std::abs(u.dot(v)) < cosAngle) continue;
      const Eigen::Vector3d pb = tfB * cb.point;
      Eigen::Vector3d off = pb - pa;
      off -= u * u.dot(off);
      if (off.norm() > tol.distance + tol.radius) continue;
      // Axial intervals along u; a shift x of A's overlaps B's by more than the tolerance for x in (lo, hi).
      const double a0 = 0.0, a1 = ca.length;
      const double bStart = u.dot(pb - pa), bEnd = bStart + cb.length * u.dot(v);
      const double b0 = std::min(bStart, bEnd), b1 = std::max(bStart, bEnd);
      const double lo = b0 + tol.distance - a1, hi = b1 - tol.distance - a0;
      if (!(lo < hi)) continue;
      // x = k t for a travel t >= 0.
      const double t = k > 0.0 ? (hi <= 0.0 ? std::numeric_limits<double>::infinity() : std::max(0.0, lo) / k)
                               : (lo >= 0.0 ? std::numeric_limits<double>::infinity() : std::max(0.0, -hi) / -k);
      first = std::min(first, t);
    }
  }
  return first;
}

}  // namespace vaw::collision
