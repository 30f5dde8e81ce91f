// What a support may do without meeting anything (docs/collision.md, "Free motion"): the geometry found once
// per support (CollisionWorld::prepare) and the free motion at a pose.
#include "collision_world_impl.hpp"

namespace vaw::collision {

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
