// The touching check of a part on the base (docs/collision.md, "Touching"). Uses only the surface patches
// found at load, never a mesh query: a plane support is decided in the base plane's 2-D coordinates from
// the faces' outlines, an axis support from the cylinders' axial extents.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>

#include "collision_world_impl.hpp"
#include "geometry2d.hpp"
#include "vaw/collision/collision_world.hpp"

namespace vaw::collision {

std::vector<int> detail::cylindersOnAxis(const SurfacePatches& sp, const Axis& axis, const Tolerances& tol) {
  const double cosA = std::cos(tol.angle);
  std::vector<int> found;
  for (std::size_t i = 0; i < sp.cylinders.size(); ++i) {
    const CylindricalPatch& c = sp.cylinders[i];
    Eigen::Vector3d d = c.point - axis.point;
    d -= axis.direction * axis.direction.dot(d);
    if (std::abs(c.direction.dot(axis.direction)) >= cosA && d.norm() <= tol.distance + tol.radius) found.push_back(static_cast<int>(i));
  }
  return found;
}

namespace {

using geom2::perpendicular;

double lineDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& linePoint, const Eigen::Vector3d& u) {
  Eigen::Vector3d d = p - linePoint;
  return (d - u * u.dot(d)).norm();
}

// Planar patches lying in a plane; `normal` is flipped to the patches' outward side when they face the
// other way (a constraint written with an inward normal).
std::vector<int> patchesInPlane(const SurfacePatches& sp, Plane& plane, const Tolerances& tol) {
  const double cosA = std::cos(tol.angle);
  for (double sign : {1.0, -1.0}) {
    std::vector<int> found;
    const Eigen::Vector3d n = sign * plane.normal;
    for (std::size_t i = 0; i < sp.planes.size(); ++i) {
      const PlanarPatch& p = sp.planes[i];
      if (p.normal.dot(n) >= cosA && std::abs(n.dot(p.origin - plane.point)) <= tol.distance)
        found.push_back(static_cast<int>(i));
    }
    if (!found.empty()) {
      plane.normal = n;
      return found;
    }
  }
  return {};
}

// Radial clearance of a bore on a shaft (opposite kinds): the bore's radius minus the shaft's; negative
// for interference.
double clearanceOf(const CylindricalPatch& a, const CylindricalPatch& b) {
  return a.convex ? b.radius - a.radius : a.radius - b.radius;
}

// Millimetres to 0.1 um, trailing zeros dropped: meshes written in single precision put radii a few
// hundredths of a micrometre off, which is not a clearance worth printing.
std::string mm(double metres) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.4f", 1e3 * metres);
  std::string out = buf;
  while (out.back() == '0') out.pop_back();
  if (out.back() == '.') out.pop_back();
  if (out == "-0") out = "0";
  return out + " mm";
}

// `designed`: the radial interference the constraint was found with by design (a thread at its tap
// drill, a press fit), which fits like a clearance of 0.
void matchAxis(Support& s, const SurfacePatches& pp, const SurfacePatches& bp, const Tolerances& tol, double designed) {
  const std::vector<int> pc = detail::cylindersOnAxis(pp, s.partAxis, tol);
  const std::vector<int> bc = detail::cylindersOnAxis(bp, s.baseAxis, tol);
  // Every bore-and-shaft pair on the axis by its clearance. The fit is the tightest pair that is not
  // interference (a sleeve's bore on the shaft, not its outside in some wider bore of the base), with
  // every pair as tight as it within the radius tolerance (a shaft in two bearing seats).
  struct Pair {
    int i, j;
    double clearance;
  };
  std::vector<Pair> pairs;
  for (int i : pc)
    for (int j : bc) {
      const CylindricalPatch& a = pp.cylinders[static_cast<std::size_t>(i)];
      const CylindricalPatch& b = bp.cylinders[static_cast<std::size_t>(j)];
      if (a.convex != b.convex) pairs.push_back({i, j, clearanceOf(a, b)});
    }
  const Pair* tightest = nullptr;
  const Pair* leastInterference = nullptr;
  const double least = -tol.radius - designed;
  for (const Pair& p : pairs) {
    if (p.clearance >= least) {
      if (!tightest || p.clearance < tightest->clearance) tightest = &p;
    } else if (!leastInterference || p.clearance > leastInterference->clearance) {
      leastInterference = &p;
    }
  }
  if (!tightest) {
    if (leastInterference) {
      const CylindricalPatch& a = pp.cylinders[static_cast<std::size_t>(leastInterference->i)];
      const CylindricalPatch& b = bp.cylinders[static_cast<std::size_t>(leastInterference->j)];
      const CylindricalPatch& bore = a.convex ? b : a;
      const CylindricalPatch& shaft = a.convex ? a : b;
      s.partRadius = a.radius;
      s.baseRadius = b.radius;
      s.partIsBore = !a.convex;
      s.clearance = leastInterference->clearance;
      s.problem = "interference: the " + std::string(a.convex ? "base's bore" : "part's bore") + " (r = " + mm(bore.radius) +
                  ") is " + mm(-leastInterference->clearance) + " smaller than the " +
                  std::string(a.convex ? "part's shaft" : "base's shaft") + " (r = " + mm(shaft.radius) +
                  "); a bore fits a shaft when it is at least as large (to within " + mm(tol.radius) + ")";
    } else if (pc.empty() || bc.empty()) {
      s.problem = "no cylindrical surface on the constraint axis (part: " + std::to_string(pc.size()) +
                  ", base: " + std::to_string(bc.size()) + ")";
    } else {
      s.problem = "no bore and shaft pair on the constraint axis (the part's and the base's cylinders there are all shafts or all bores)";
    }
    return;
  }
  s.clearance = std::max(0.0, tightest->clearance);
  s.partRadius = pp.cylinders[static_cast<std::size_t>(tightest->i)].radius;
  s.partIsBore = !pp.cylinders[static_cast<std::size_t>(tightest->i)].convex;
  s.baseRadius = bp.cylinders[static_cast<std::size_t>(tightest->j)].radius;
  for (const Pair& p : pairs) {
    if (p.clearance < least || p.clearance > std::max(tightest->clearance, 0.0) + tol.radius) continue;
    s.fitPairs.emplace_back(p.i, p.j);
    if (std::find(s.partPatches.begin(), s.partPatches.end(), p.i) == s.partPatches.end()) s.partPatches.push_back(p.i);
    if (std::find(s.basePatches.begin(), s.basePatches.end(), p.j) == s.basePatches.end()) s.basePatches.push_back(p.j);
  }
}

}  // namespace

Support matchSupport(const Constraint& c, PartId base, const SurfacePatches* pp, const SurfacePatches* bp, const Tolerances& tol) {
  Support s;
  s.part = c.part;
  s.base = base;
  s.offset = c.offset;
  if (c.type == Constraint::Type::Align) {
    s.problem = "an align constraint has no contact face; touching is defined for mate and insert constraints";
    return s;
  }
  if (c.type == Constraint::Type::Mate) {
    s.kind = Support::Kind::Plane;
    s.partPlane = {c.partPlane.point, c.partPlane.normal.normalized()};
    s.basePlane = {c.basePlane.point, c.basePlane.normal.normalized()};
    if (!pp || !bp) {
      s.problem = "part or base has no mesh to find the constraint faces on";
      return s;
    }
    s.partPatches = patchesInPlane(*pp, s.partPlane, tol);
    s.basePatches = patchesInPlane(*bp, s.basePlane, tol);
    if (s.partPatches.empty()) s.problem = "no face of the part lies in the constraint's part plane";
    else if (s.basePatches.empty()) s.problem = "no face of the base lies in the constraint's base plane";
    return s;
  }
  s.kind = Support::Kind::Axis;
  s.partAxis = {c.partAxis.point, c.partAxis.direction.normalized()};
  s.baseAxis = {c.baseAxis.point, c.baseAxis.direction.normalized()};
  if (!pp || !bp) {
    s.problem = "part or base has no mesh to find the constraint cylinders on";
    return s;
  }
  const bool designed = c.found && c.found->fit != Constraint::Found::Fit::Clearance;
  matchAxis(s, *pp, *bp, tol, designed ? c.found->interference : 0.0);
  return s;
}

std::string describeFit(const Support& s) {
  const std::string kind = s.kind == Support::Kind::Axis ? "insert: " : "mate: ";
  if (!s.problem.empty()) return kind + s.problem;
  if (s.kind == Support::Kind::Plane) {
    const auto faces = [](std::size_t n) { return std::to_string(n) + (n == 1 ? " face" : " faces"); };
    return kind + faces(s.partPatches.size()) + " of the part on " + faces(s.basePatches.size()) + " of the base";
  }
  const bool partIsBore = s.partIsBore;
  return kind + "the part's " + (partIsBore ? "bore" : "shaft") + " (r = " + mm(s.partRadius) + ") " + (partIsBore ? "on" : "in") +
         " the base's " + (partIsBore ? "shaft" : "bore") + " (r = " + mm(s.baseRadius) + "), clearance " + mm(s.clearance);
}

std::vector<ConstraintFit> constraintFits(const Assembly& a, const Tolerances& tol) {
  std::vector<ConstraintFit> out;
  if (!a.base) return out;
  std::vector<std::optional<SurfacePatches>> patches(a.parts.size());
  const auto of = [&](PartId id) -> const SurfacePatches* {
    if (id >= a.parts.size() || !a.parts[id].mesh) return nullptr;
    if (!patches[id]) patches[id] = classifySurfaces(*a.parts[id].mesh, a.parts[id].cad.get());
    return &*patches[id];
  };
  for (std::size_t i = 0; i < a.constraints.size(); ++i) {
    const Constraint& c = a.constraints[i];
    ConstraintFit f;
    f.constraint = i;
    // A constraint to another part is matched against that part's surfaces the same way.
    const PartId partner = c.partner.value_or(*a.base);
    f.support = c.type == Constraint::Type::Align ? matchSupport(c, partner, nullptr, nullptr, tol)
                                                  : matchSupport(c, partner, of(c.part), of(partner), tol);
    f.text = describeFit(f.support);
    out.push_back(std::move(f));
  }
  return out;
}

Support CollisionWorld::support(const Constraint& c, bool prepared) const {
  if (!base()) {
    Support s;
    s.part = c.part;
    s.problem = "the assembly has no base";
    return s;
  }
  // A constraint to another part rests the part on that part's surfaces, wherever the partner is.
  const PartId partner = c.partner.value_or(*base());
  Support s = matchSupport(c, partner, patches(ObjectId::part(c.part)), patches(ObjectId::part(partner)), tolerances());
  if (prepared) prepare(s);
  return s;
}

TouchResult CollisionWorld::touching(const Support& s) const { return touching(s, pose(ObjectId::part(s.part))); }

TouchResult CollisionWorld::touching(const Support& s, const Eigen::Isometry3d& partPose) const {
  TouchResult r;
  r.margin = -std::numeric_limits<double>::infinity();
  if (!s.problem.empty()) {
    r.reason = s.problem;
    return r;
  }
  const Tolerances& tol = tolerances();
  const SurfacePatches& pp = *patches(ObjectId::part(s.part));
  const SurfacePatches& bp = *patches(ObjectId::part(s.base));
  const Eigen::Isometry3d& baseToWorld = pose(ObjectId::part(s.base));
  const Eigen::Isometry3d partToBase = baseToWorld.inverse() * partPose;

  if (s.kind == Support::Kind::Axis) {
    const Eigen::Vector3d ub = s.baseAxis.direction, ob = s.baseAxis.point;
    const Eigen::Vector3d up = partToBase.linear() * s.partAxis.direction, op = partToBase * s.partAxis.point;
    r.separation = lineDistance(op, ob, ub);
    if (std::abs(up.dot(ub)) < std::cos(tol.angle)) {
      r.reason = "the part's axis is tilted off the base's axis";
      return r;
    }
    if (r.separation > tol.distance + tol.radius + s.clearance) {
      r.reason = "the part's axis is off the base's axis";
      return r;
    }
    auto interval = [&](const CylindricalPatch& c, const Eigen::Isometry3d& toBase) {
      const double a = ub.dot(toBase * c.point - ob);
      const double b = ub.dot(toBase * Eigen::Vector3d(c.point + c.length * c.direction) - ob);
      return std::pair{std::min(a, b), std::max(a, b)};
    };
    for (const auto& [i, j] : s.fitPairs) {
      const auto [p0, p1] = interval(pp.cylinders[static_cast<std::size_t>(i)], partToBase);
      const auto [b0, b1] = interval(bp.cylinders[static_cast<std::size_t>(j)], Eigen::Isometry3d::Identity());
      r.margin = std::max(r.margin, std::min(p1, b1) - std::max(p0, b0));
    }
    r.touching = r.margin >= -tol.distance;
    if (!r.touching) r.reason = "the part has slid off the base's cylinder";
    return r;
  }

  // Plane: everything in the base frame, then in the base plane's 2-D coordinates.
  const Eigen::Vector3d nb = s.basePlane.normal, ob = s.basePlane.point;
  const Eigen::Vector3d np = partToBase.linear() * s.partPlane.normal;
  const Eigen::Vector3d e1 = perpendicular(nb), e2 = nb.cross(e1);
  auto to2 = [&](const Eigen::Vector3d& x) { return geom2::P(e1.dot(x - ob), e2.dot(x - ob)); };
  auto toWorld = [&](const geom2::P& q) { return Eigen::Vector3d(baseToWorld * Eigen::Vector3d(ob + q.x() * e1 + q.y() * e2)); };
  r.separation = nb.dot(partToBase * s.partPlane.point - ob) - s.offset;
  const geom2::P com = to2(partToBase * centreOfMass(s.part));
  r.comProjection = toWorld(com);
  if (-np.dot(nb) < std::cos(tol.angle)) {
    r.reason = "the part's face is tilted against the base's face";
    return r;
  }
  if (std::abs(r.separation) > tol.distance) {
    r.reason = r.separation > 0.0 ? "the part's face is off the base's face" : "the part's face is sunk into the base's face";
    return r;
  }
  std::vector<geom2::Segment> A, B;
  std::vector<geom2::P> aPts, bPts, aHull;
  geom2::Box aBox;
  for (int i : s.partPatches) {
    const PlanarPatch& p = pp.planes[static_cast<std::size_t>(i)];
    for (const Outline& loop : p.outline) {
      const std::size_t n0 = aPts.size();
      for (const auto& q : loop) {
        aPts.push_back(to2(partToBase * p.toMesh(q)));
        aBox.extend(aPts.back());
      }
      for (std::size_t k = 0; k < loop.size(); ++k) A.push_back({aPts[n0 + k], aPts[n0 + (k + 1) % loop.size()]});
    }
    for (const auto& q : p.hull) aHull.push_back(to2(partToBase * p.toMesh(q)));
  }
  for (int i : s.basePatches) {
    const PlanarPatch& p = bp.planes[static_cast<std::size_t>(i)];
    for (const Outline& loop : p.outline) {
      const std::size_t n0 = bPts.size();
      for (const auto& q : loop) bPts.push_back(to2(p.toMesh(q)));
      for (std::size_t k = 0; k < loop.size(); ++k) B.push_back({bPts[n0 + k], bPts[n0 + (k + 1) % loop.size()]});
    }
  }
  if (aPts.empty() || bPts.empty()) {
    r.reason = "no outline on the contact faces";
    return r;
  }
  // The convex hull of the overlap of the two faces: its corners are corners of either outline inside the
  // other, or crossings of the outlines. If no base edge comes near the part's face, the overlap is the
  // whole face or nothing.
  const geom2::Box near = aBox.inflated(tol.distance);
  std::vector<const geom2::Segment*> bNear;
  for (const auto& seg : B)
    if (near.overlaps(geom2::boxOf(seg))) bNear.push_back(&seg);
  std::vector<geom2::P> candidates;
  auto insideB = [&](const geom2::P& q) { return geom2::insideRegion(q, B) || geom2::distanceToEdges(q, B) <= tol.distance; };
  if (bNear.empty()) {
    if (geom2::insideRegion(aPts.front(), B)) candidates = aHull;
  } else {
    for (const auto& q : aPts)
      if (insideB(q)) candidates.push_back(q);
    for (const auto& q : bPts)
      if (near.contains(q) && (geom2::insideRegion(q, A) || geom2::distanceToEdges(q, A) <= tol.distance)) candidates.push_back(q);
    for (const auto& sa : A) {
      const geom2::Box ba = geom2::boxOf(sa);
      for (const geom2::Segment* sb : bNear)
        if (ba.overlaps(geom2::boxOf(*sb)))
          if (auto x = geom2::intersect(sa, *sb)) candidates.push_back(*x);
    }
  }
  const std::vector<geom2::P> hull = geom2::convexHull(std::move(candidates));
  if (hull.empty()) {
    r.reason = "the part's face no longer overlaps the base's face";
    return r;
  }
  r.supportArea = std::abs(geom2::area(hull));
  for (const auto& q : hull) r.supportPolygon.push_back(toWorld(q));
  r.margin = geom2::signedDistanceConvex(com, hull);
  r.touching = r.margin >= -tol.distance;
  if (!r.touching) r.reason = "the centre of mass has passed the edge of the support";
  return r;
}

}  // namespace vaw::collision
