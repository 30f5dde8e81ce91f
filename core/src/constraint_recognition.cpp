#include "vaw/constraint_recognition.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <queue>

#include "collision/geometry2d.hpp"

namespace vaw {

namespace {

namespace g2 = collision::geom2;
using g2::P;

// Sutherland-Hodgman: the part of convex polygon `subject` inside convex counter-clockwise `clip`.
std::vector<P> clipConvex(std::vector<P> subject, const std::vector<P>& clip) {
  for (std::size_t i = 0; i < clip.size() && !subject.empty(); ++i) {
    const P& a = clip[i];
    const P& b = clip[(i + 1) % clip.size()];
    const auto side = [&](const P& p) { return g2::cross(b - a, p - a); };
    std::vector<P> out;
    out.reserve(subject.size() + 2);
    for (std::size_t j = 0; j < subject.size(); ++j) {
      const P& cur = subject[j];
      const P& prev = subject[(j + subject.size() - 1) % subject.size()];
      const double sc = side(cur), sp = side(prev);
      if (sc >= 0.0) {
        if (sp < 0.0) out.push_back(prev + (cur - prev) * (sp / (sp - sc)));
        out.push_back(cur);
      } else if (sp >= 0.0) {
        out.push_back(prev + (cur - prev) * (sp / (sp - sc)));
      }
    }
    subject = std::move(out);
  }
  return subject;
}

struct Tri2 {
  std::vector<P> corners;  // counter-clockwise
  Eigen::AlignedBox2d box;
};

// A planar face's triangles in the 2-D frame (origin, e1, e2) of the common plane.
std::vector<Tri2> faceTriangles(const CadSolid& s, const CadFace& f, const Eigen::Isometry3d& pose, const Eigen::Vector3d& origin,
                                const Eigen::Vector3d& e1, const Eigen::Vector3d& e2) {
  std::vector<Tri2> out;
  out.reserve(f.triangleCount);
  for (std::size_t t = f.firstTriangle; t < f.firstTriangle + f.triangleCount && t < s.mesh.triangles.size(); ++t) {
    Tri2 tri;
    for (int k = 0; k < 3; ++k) {
      const auto vi = static_cast<std::size_t>(s.mesh.triangles[t][k]);
      if (vi >= s.mesh.vertices.size()) return {};
      const Eigen::Vector3d w = pose * s.mesh.vertices[vi] - origin;
      tri.corners.emplace_back(w.dot(e1), w.dot(e2));
      tri.box.extend(tri.corners.back());
    }
    if (g2::area(tri.corners) < 0.0) std::reverse(tri.corners.begin(), tri.corners.end());
    out.push_back(std::move(tri));
  }
  return out;
}

Eigen::Vector3d anyPerpendicular(const Eigen::Vector3d& n) {
  const Eigen::Vector3d t = std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return n.cross(t).normalized();
}

struct WorldFace {
  const CadFace* face = nullptr;
  std::size_t index = 0;
  Eigen::Vector3d point, direction;
  double axialMin = 0.0, axialMax = 0.0;
};

std::vector<WorldFace> worldFaces(const RecognitionPart& p, CadFace::Surface kind) {
  std::vector<WorldFace> out;
  if (!p.solid) return out;
  for (std::size_t i = 0; i < p.solid->faces.size(); ++i) {
    const CadFace& f = p.solid->faces[i];
    if (f.surface != kind) continue;
    WorldFace w;
    w.face = &f;
    w.index = i;
    w.point = p.pose * f.point;
    w.direction = (p.pose.linear() * f.direction).normalized();
    w.axialMin = f.axialMin;
    w.axialMax = f.axialMax;
    out.push_back(w);
  }
  return out;
}

// World bounds at the assembled pose (empty for a part without a solid).
Eigen::AlignedBox3d worldBox(const RecognitionPart& p) {
  Eigen::AlignedBox3d b;
  if (p.solid)
    for (const auto& v : p.solid->mesh.vertices) b.extend(p.pose * v);
  return b;
}

}  // namespace

double coplanarOverlapArea(const CadSolid& a, const CadFace& fa, const Eigen::Isometry3d& poseA, const CadSolid& b,
                           const CadFace& fb, const Eigen::Isometry3d& poseB) {
  const Eigen::Vector3d n = (poseA.linear() * fa.direction).normalized();
  const Eigen::Vector3d e1 = anyPerpendicular(n), e2 = n.cross(e1);
  const Eigen::Vector3d origin = poseA * fa.point;
  const std::vector<Tri2> ta = faceTriangles(a, fa, poseA, origin, e1, e2);
  const std::vector<Tri2> tb = faceTriangles(b, fb, poseB, origin, e1, e2);
  double total = 0.0;
  for (const Tri2& x : ta)
    for (const Tri2& y : tb) {
      if (!x.box.intersects(y.box)) continue;
      const std::vector<P> common = clipConvex(x.corners, y.corners);
      if (common.size() >= 3) total += std::abs(g2::area(common));
    }
  return total;
}

std::vector<FoundConstraint> recognizeConstraints(const std::vector<RecognitionPart>& parts, const RecognitionTolerances& tol) {
  std::vector<FoundConstraint> out;
  std::vector<Eigen::AlignedBox3d> boxes;
  for (const auto& p : parts) boxes.push_back(worldBox(p));
  const double margin = tol.distance + tol.maxClearance;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    for (std::size_t j = i + 1; j < parts.size(); ++j) {
      const RecognitionPart& A = parts[i];
      const RecognitionPart& B = parts[j];
      if (boxes[i].isEmpty() || boxes[j].isEmpty()) continue;
      Eigen::AlignedBox3d grown = boxes[i];
      grown.min().array() -= margin;
      grown.max().array() += margin;
      if (!grown.intersects(boxes[j])) continue;

      // Inserts: a convex cylinder inside a concave one on (nearly) the same axis, overlapping along it.
      const auto cylA = worldFaces(A, CadFace::Surface::Cylinder), cylB = worldFaces(B, CadFace::Surface::Cylinder);
      for (const WorldFace& x : cylA)
        for (const WorldFace& y : cylB) {
          if (x.face->convex == y.face->convex) continue;
          const WorldFace& shaft = x.face->convex ? x : y;
          const WorldFace& bore = x.face->convex ? y : x;
          if (shaft.direction.cross(bore.direction).norm() > tol.angle) continue;
          const Eigen::Vector3d u = bore.direction;
          const Eigen::Vector3d rel = shaft.point - bore.point;
          if ((rel - u * u.dot(rel)).norm() > tol.distance) continue;
          const double clearance = bore.face->radius - shaft.face->radius;
          if (clearance < -tol.distance) continue;  // a press fit with interference is not read as an insert
          if (clearance > std::min(tol.maxClearance, tol.maxClearanceRel * bore.face->radius)) continue;
          // Both faces' extents along the bore's axis, from the bore's axis point.
          const double s = shaft.direction.dot(u) >= 0.0 ? 1.0 : -1.0;
          const double shift = u.dot(rel);
          double s0 = shift + s * shaft.axialMin, s1 = shift + s * shaft.axialMax;
          if (s0 > s1) std::swap(s0, s1);
          const double overlap = std::min(s1, bore.axialMax) - std::max(s0, bore.axialMin);
          const double shorter = std::min(s1 - s0, bore.axialMax - bore.axialMin);
          if (!(overlap > tol.minOverlapRel * shorter && overlap > tol.distance)) continue;
          FoundConstraint f;
          f.type = Constraint::Type::Insert;
          f.a = i;
          f.b = j;
          f.faceA = x.index;
          f.faceB = y.index;
          f.point = bore.point;
          f.direction = u;
          f.found.partRadius = x.face->radius;
          f.found.partnerRadius = y.face->radius;
          f.found.clearance = std::max(0.0, clearance);
          f.found.overlap = overlap;
          f.found.fromSpline = x.face->fromSpline || y.face->fromSpline;
          out.push_back(f);
        }

      // Mates: opposed normals, one plane, and a common area that is more than an edge.
      const auto plA = worldFaces(A, CadFace::Surface::Plane), plB = worldFaces(B, CadFace::Surface::Plane);
      for (const WorldFace& x : plA)
        for (const WorldFace& y : plB) {
          if (x.direction.dot(y.direction) > -1.0 + 0.5 * tol.angle * tol.angle) continue;
          if (std::abs(x.direction.dot(y.point - x.point)) > tol.distance) continue;
          const double area = coplanarOverlapArea(*A.solid, *x.face, A.pose, *B.solid, *y.face, B.pose);
          const double smaller = std::min(x.face->area, y.face->area);
          if (!(area > tol.minOverlapRel * smaller)) continue;
          FoundConstraint f;
          f.type = Constraint::Type::Mate;
          f.a = i;
          f.b = j;
          f.faceA = x.index;
          f.faceB = y.index;
          f.point = x.point;
          f.direction = x.direction;
          f.found.overlap = area;
          f.found.fromSpline = x.face->fromSpline || y.face->fromSpline;
          out.push_back(f);
        }
    }
  }
  return out;
}

std::vector<Constraint> constraintsFromFound(const std::vector<FoundConstraint>& found, const std::vector<Part>& parts, PartId base,
                                             const std::vector<Eigen::Isometry3d>& finalPoses) {
  const std::size_t n = parts.size();
  // Hops from the base over the contact graph: the base goes first, then what touches it, and so on.
  std::vector<std::vector<std::size_t>> next(n);
  for (const FoundConstraint& f : found) {
    next[f.a].push_back(f.b);
    next[f.b].push_back(f.a);
  }
  std::vector<std::size_t> hops(n, std::numeric_limits<std::size_t>::max());
  std::queue<std::size_t> q;
  hops[base] = 0;
  q.push(base);
  while (!q.empty()) {
    const std::size_t k = q.front();
    q.pop();
    for (std::size_t m : next[k])
      if (hops[m] == std::numeric_limits<std::size_t>::max()) {
        hops[m] = hops[k] + 1;
        q.push(m);
      }
  }
  std::vector<double> lowest(n, 0.0);
  for (std::size_t k = 0; k < n; ++k) {
    if (!parts[k].mesh) continue;
    double z = std::numeric_limits<double>::infinity();
    for (const auto& v : parts[k].mesh->vertices) z = std::min(z, (finalPoses[k] * v).z());
    lowest[k] = z;
  }
  // True when `x` is assembled before `y`, so `x` is the partner.
  const auto before = [&](std::size_t x, std::size_t y) {
    if (x == base || y == base) return x == base;
    if (hops[x] != hops[y]) return hops[x] < hops[y];
    const double eps = 1e-6;
    if (std::abs(lowest[x] - lowest[y]) > eps) return lowest[x] < lowest[y];
    if (parts[x].mass.mass != parts[y].mass.mass) return parts[x].mass.mass > parts[y].mass.mass;
    return x < y;
  };

  std::vector<Constraint> out;
  std::map<std::tuple<std::size_t, std::size_t, int>, int> seen;
  for (const FoundConstraint& f : found) {
    const bool aFirst = before(f.a, f.b);
    const std::size_t part = aFirst ? f.b : f.a, partner = aFirst ? f.a : f.b;
    // Several faces of one pair can give the same kind (a stepped shaft): each is kept, numbered.
    const int count = ++seen[{part, partner, static_cast<int>(f.type)}];
    const Eigen::Isometry3d toPart = finalPoses[part].inverse(), toPartner = finalPoses[partner].inverse();
    Constraint c;
    c.type = f.type;
    c.part = part;
    if (partner != base) c.partner = partner;
    c.found = f.found;
    if (!aFirst && f.type == Constraint::Type::Insert) std::swap(c.found->partRadius, c.found->partnerRadius);
    const std::string kind(name(f.type));
    c.name = kind + " " + parts[part].name + " on " + parts[partner].name + (count > 1 ? " " + std::to_string(count) : "");
    const Eigen::Vector3d comPart = finalPoses[part] * parts[part].mass.centerOfMass;
    if (f.type == Constraint::Type::Insert) {
      c.partAxis = {toPart * f.point, (toPart.linear() * f.direction).normalized()};
      c.baseAxis = {toPartner * f.point, (toPartner.linear() * f.direction).normalized()};
      // The part comes from the side of the partner's face its centre of mass lies on.
      const CadFace& pf = parts[partner].cad->faces[aFirst ? f.faceA : f.faceB];
      const Eigen::Vector3d mid = finalPoses[partner] * (pf.point + pf.direction * 0.5 * (pf.axialMin + pf.axialMax));
      double side = f.direction.dot(comPart - mid);
      if (std::abs(side) < 1e-9) side = f.direction.z();
      c.homeDirection = (toPartner.linear() * (side >= 0.0 ? f.direction : Eigen::Vector3d(-f.direction))).normalized();
    } else {
      // f.direction is a's outward normal; the partner's plane normal points out of the partner, at the part.
      const Eigen::Vector3d partnerNormal = aFirst ? f.direction : Eigen::Vector3d(-f.direction);
      c.partPlane = {toPart * f.point, (toPart.linear() * -partnerNormal).normalized()};
      c.basePlane = {toPartner * f.point, (toPartner.linear() * partnerNormal).normalized()};
      c.offset = 0.0;
      c.homeDirection = c.basePlane.normal;
    }
    out.push_back(std::move(c));
  }
  // Grouped by part, inserts first: a released part is tried on its axes before its planes, since an axis
  // also fixes where on the plane it sits.
  std::stable_sort(out.begin(), out.end(), [](const Constraint& x, const Constraint& y) {
    if (x.part != y.part) return x.part < y.part;
    return (x.type == Constraint::Type::Insert) > (y.type == Constraint::Type::Insert);
  });
  return out;
}

}  // namespace vaw
