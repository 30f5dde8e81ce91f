#include "vaw/constraint_recognition.hpp"

#include "vaw/collision/interference.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numbers>
#include <queue>
#include <set>
#include <tuple>

#include "../collision/geometry2d.hpp"
#include "vaw/collision/interference.hpp"
#include "vaw/fits.hpp"

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

// A planar face's triangles in the 2-D frame (origin, e1, e2) of the common plane; with `within`, only
// those whose box meets it (a 2 m plate's face has thousands of triangles, the washer on it a few dozen).
// `only`: just these of its triangles (ascending), where a FaceGrid has found the few that can matter.
std::vector<Tri2> faceTriangles(const CadSolid& s, const CadFace& f, const Eigen::Isometry3d& pose, const Eigen::Vector3d& origin,
                                const Eigen::Vector3d& e1, const Eigen::Vector3d& e2, const Eigen::AlignedBox2d* within = nullptr,
                                const std::vector<std::size_t>* only = nullptr) {
  std::vector<Tri2> out;
  if (!within) out.reserve(f.triangleCount);
  const std::size_t end = std::min(f.firstTriangle + f.triangleCount, s.mesh.triangles.size());
  const std::size_t count = only ? only->size() : end - std::min(f.firstTriangle, end);
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t t = only ? (*only)[i] : f.firstTriangle + i;
    if (t >= end) continue;
    std::array<P, 3> corners;
    Eigen::AlignedBox2d box;
    for (int k = 0; k < 3; ++k) {
      const auto vi = static_cast<std::size_t>(s.mesh.triangles[t][k]);
      if (vi >= s.mesh.vertices.size()) return {};
      const Eigen::Vector3d w = pose * s.mesh.vertices[vi] - origin;
      corners[static_cast<std::size_t>(k)] = P(w.dot(e1), w.dot(e2));
      box.extend(corners[static_cast<std::size_t>(k)]);
    }
    if (within && !box.intersects(*within)) continue;
    Tri2 tri{std::vector<P>(corners.begin(), corners.end()), box};
    if (g2::area(tri.corners) < 0.0) std::reverse(tri.corners.begin(), tri.corners.end());
    out.push_back(std::move(tri));
  }
  return out;
}

Eigen::Vector3d anyPerpendicular(const Eigen::Vector3d& n) {
  const Eigen::Vector3d t = std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return n.cross(t).normalized();
}

// A large planar face's triangles in a grid over its plane, in its solid's frame, so that the few that can
// meet a small face lying on it are found without projecting every one: a 2.8 m plate's face has tens of
// thousands of triangles and meets a thousand small faces.
class FaceGrid {
 public:
  FaceGrid(const CadSolid& s, const CadFace& f)
      : origin_(f.point), e1_(anyPerpendicular(f.direction.normalized())), e2_(f.direction.normalized().cross(e1_)) {
    const std::size_t end = std::min(f.firstTriangle + f.triangleCount, s.mesh.triangles.size());
    std::vector<std::pair<std::size_t, Eigen::AlignedBox2d>> boxes;
    double sizes = 0.0;
    for (std::size_t t = f.firstTriangle; t < end; ++t) {
      Eigen::AlignedBox2d box;
      for (int k = 0; k < 3; ++k) {
        const auto vi = static_cast<std::size_t>(s.mesh.triangles[t][k]);
        if (vi < s.mesh.vertices.size()) box.extend(project(s.mesh.vertices[vi]));
      }
      if (box.isEmpty()) continue;
      bounds_.extend(box);
      sizes += box.sizes().maxCoeff();
      boxes.emplace_back(t, box);
    }
    if (boxes.empty()) return;
    // Cells about a triangle's size, and no more of them than triangles.
    const double n = static_cast<double>(boxes.size());
    cell_ = std::max({sizes / n, std::sqrt(bounds_.sizes().prod() / n), bounds_.sizes().maxCoeff() / 512.0, 1e-9});
    nx_ = static_cast<int>(bounds_.sizes().x() / cell_) + 1;
    ny_ = static_cast<int>(bounds_.sizes().y() / cell_) + 1;
    cells_.resize(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_));
    for (const auto& entry : boxes) {
      const std::size_t t = entry.first;  // clang 14 takes no structured binding into a lambda
      forCells(entry.second, [&](std::vector<std::size_t>& c) { c.push_back(t); });
    }
  }
  [[nodiscard]] Eigen::Vector2d project(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d d = p - origin_;
    return {d.dot(e1_), d.dot(e2_)};
  }
  // Ascending indices of the triangles whose boxes may meet `box` (in the grid's plane coordinates).
  [[nodiscard]] std::vector<std::size_t> near(const Eigen::AlignedBox2d& box) const {
    std::vector<std::size_t> out;
    if (cells_.empty()) return out;
    const_cast<FaceGrid*>(this)->forCells(box, [&](std::vector<std::size_t>& c) { out.insert(out.end(), c.begin(), c.end()); });
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }

 private:
  template <class Visit>
  void forCells(const Eigen::AlignedBox2d& box, Visit&& visit) {
    const auto index = [&](double v, double lo, int n) {
      return std::clamp(static_cast<int>(std::floor((v - lo) / cell_)), 0, n - 1);
    };
    if (box.isEmpty() || !box.intersects(bounds_)) return;
    const int x0 = index(box.min().x(), bounds_.min().x(), nx_), x1 = index(box.max().x(), bounds_.min().x(), nx_);
    const int y0 = index(box.min().y(), bounds_.min().y(), ny_), y1 = index(box.max().y(), bounds_.min().y(), ny_);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x)
        visit(cells_[static_cast<std::size_t>(y) * static_cast<std::size_t>(nx_) + static_cast<std::size_t>(x)]);
  }
  Eigen::Vector3d origin_, e1_, e2_;
  Eigen::AlignedBox2d bounds_;
  double cell_ = 1.0;
  int nx_ = 0, ny_ = 0;
  std::vector<std::vector<std::size_t>> cells_;
};

// The grids of the large faces one recognition meets, made when first asked for.
class FaceGrids {
 public:
  static constexpr std::size_t kLarge = 512;  // triangles
  const FaceGrid* of(const CadSolid& s, const CadFace& f) {
    if (f.triangleCount < kLarge) return nullptr;
    auto it = grids_.find(&f);
    if (it == grids_.end()) it = grids_.emplace(&f, std::make_unique<FaceGrid>(s, f)).first;
    return it->second.get();
  }

 private:
  std::map<const CadFace*, std::unique_ptr<FaceGrid>> grids_;
};

double overlapArea(const CadSolid& a, const CadFace& fa, const Eigen::Isometry3d& poseA, const CadSolid& b, const CadFace& fb,
                   const Eigen::Isometry3d& poseB, FaceGrids* grids);

struct WorldFace {
  const CadFace* face = nullptr;
  std::size_t index = 0;
  Eigen::Vector3d point, direction;
  double axialMin = 0.0, axialMax = 0.0;
};

WorldFace worldFace(const RecognitionPart& p, std::size_t i) {
  const CadFace& f = p.solid->faces[i];
  WorldFace w;
  w.face = &f;
  w.index = i;
  w.point = p.pose * f.point;
  w.direction = (p.pose.linear() * f.direction).normalized();
  w.axialMin = f.axialMin;
  w.axialMax = f.axialMax;
  return w;
}

std::vector<WorldFace> worldFaces(const RecognitionPart& p, CadFace::Surface kind) {
  std::vector<WorldFace> out;
  if (!p.solid) return out;
  for (std::size_t i = 0; i < p.solid->faces.size(); ++i)
    if (p.solid->faces[i].surface == kind) out.push_back(worldFace(p, i));
  return out;
}

// World bounds at the assembled pose (empty for a part without a solid).
Eigen::AlignedBox3d worldBox(const RecognitionPart& p) {
  Eigen::AlignedBox3d b;
  if (p.solid)
    for (const auto& v : p.solid->mesh.vertices) b.extend(p.pose * v);
  return b;
}

// Why two faces are no constraint: the test that failed, what it measured (m, m^2 or rad) and the limit.
// Kept as numbers so recognition, which tries every pair, never formats text.
enum class Refusal {
  None,
  BothHoles,
  BothShafts,
  AxesAngle,
  AxesApart,
  Interference,
  TooLoose,
  NoAxialOverlap,
  NotFacing,
  SameWay,
  PlanesApart,
  NoArea,
  ConeAngles,
  ConesApart
};

struct Verdict {
  Refusal refusal = Refusal::None;
  double value = 0.0, limit = 0.0;
};

// Two faces' extents along one axis, [a0, a1] and [b0, b1]: their overlap in `overlap`, refused when it is
// no more than a touch at an end (a fraction of the shorter, or the distance tolerance).
Verdict axialOverlap(double a0, double a1, double b0, double b1, const RecognitionTolerances& tol, double& overlap) {
  overlap = std::min(a1, b1) - std::max(a0, b0);
  const double shorter = std::min(a1 - a0, b1 - b0);
  if (!(overlap > tol.minOverlapRel * shorter && overlap > tol.distance))
    return {Refusal::NoAxialOverlap, overlap, std::max(tol.minOverlapRel * shorter, tol.distance)};
  return {};
}

// An insert found between faces x (of part a) and y along `direction` through `point`, overlapping by
// `overlap` (m) along it: what every insert records whatever the faces were.
FoundConstraint insertOf(const WorldFace& x, const WorldFace& y, const Eigen::Vector3d& point, const Eigen::Vector3d& direction,
                         double overlap) {
  FoundConstraint f;
  f.type = Constraint::Type::Insert;
  f.point = point;
  f.direction = direction;
  f.found.partRadius = x.face->radius;
  f.found.partnerRadius = y.face->radius;
  f.found.overlap = overlap;
  f.found.fromSpline = x.face->fromSpline || y.face->fromSpline;
  return f;
}

// Radii apart by less than this (m) are one radius as an export rounds it.
constexpr double kRounding = 1e-6;

// A convex cylinder inside a concave one on (nearly) the same axis, overlapping along it. On success `f`
// holds the insert, a's face being `x`.
Verdict testInsert(const WorldFace& x, const WorldFace& y, const RecognitionTolerances& tol, FoundConstraint& f) {
  if (x.face->convex == y.face->convex) return {x.face->convex ? Refusal::BothShafts : Refusal::BothHoles};
  const WorldFace& shaft = x.face->convex ? x : y;
  const WorldFace& bore = x.face->convex ? y : x;
  const double sine = shaft.direction.cross(bore.direction).norm();
  if (sine > tol.angle) return {Refusal::AxesAngle, std::atan2(sine, std::abs(shaft.direction.dot(bore.direction))), tol.angle};
  const Eigen::Vector3d u = bore.direction;
  const Eigen::Vector3d rel = shaft.point - bore.point;
  const double offAxis = (rel - u * u.dot(rel)).norm();
  if (offAxis > tol.distance) return {Refusal::AxesApart, offAxis, tol.distance};
  const double clearance = bore.face->radius - shaft.face->radius;
  // Interference is an insert where a designer models it so (a thread at its tap drill, a press fit of a
  // few micrometres); below a micrometre it is an export's rounding of an exact fit.
  std::optional<DesignedInterference> designed;
  if (clearance < -kRounding) designed = designedInterference(shaft.face->radius, bore.face->radius);
  if (clearance < -tol.distance && !designed) return {Refusal::Interference, -clearance, tol.distance};
  const double loosest = std::min(tol.maxClearance, tol.maxClearanceRel * bore.face->radius);
  if (clearance > loosest) return {Refusal::TooLoose, clearance, loosest};
  // Both faces' extents along the bore's axis, from the bore's axis point.
  const double s = shaft.direction.dot(u) >= 0.0 ? 1.0 : -1.0;
  const double shift = u.dot(rel);
  double s0 = shift + s * shaft.axialMin, s1 = shift + s * shaft.axialMax;
  if (s0 > s1) std::swap(s0, s1);
  double overlap = 0.0;
  if (const Verdict v = axialOverlap(s0, s1, bore.axialMin, bore.axialMax, tol, overlap); v.refusal != Refusal::None) return v;
  f = insertOf(x, y, bore.point, u, overlap);
  f.found.clearance = std::max(0.0, clearance);
  if (designed) {
    f.found.fit = designed->fit;
    f.found.thread = designed->thread;
    f.found.interference = -clearance;
  }
  return {};
}

// A countersunk head in its countersink: a convex cone on a concave one, widening the same way on one
// axis, with one half angle and one apex (so the surfaces are one), overlapping along the axis. On success
// `f` holds the seat as an insert along the countersink's axis, a's face being `x`.
Verdict testCountersink(const WorldFace& x, const WorldFace& y, const RecognitionTolerances& tol, FoundConstraint& f) {
  if (x.face->convex == y.face->convex) return {x.face->convex ? Refusal::BothShafts : Refusal::BothHoles};
  const WorldFace& head = x.face->convex ? x : y;
  const WorldFace& sink = x.face->convex ? y : x;
  const double cosine = head.direction.dot(sink.direction);
  if (cosine < std::cos(tol.angle)) return {Refusal::AxesAngle, std::acos(std::clamp(cosine, -1.0, 1.0)), tol.angle};
  const double angles = std::abs(head.face->halfAngle - sink.face->halfAngle);
  if (angles > tol.angle) return {Refusal::ConeAngles, angles, tol.angle};
  const Eigen::Vector3d u = sink.direction, rel = head.point - sink.point;
  const double along = u.dot(rel), offAxis = (rel - u * along).norm();
  if (offAxis > tol.distance) return {Refusal::AxesApart, offAxis, tol.distance};
  // Apexes apart along the axis: the surfaces stand apart by that times the sine of the half angle.
  const double gap = std::abs(along) * std::sin(sink.face->halfAngle);
  if (gap > tol.distance) return {Refusal::ConesApart, gap, tol.distance};
  double overlap = 0.0;
  if (const Verdict v = axialOverlap(along + head.axialMin, along + head.axialMax, sink.axialMin, sink.axialMax, tol, overlap);
      v.refusal != Refusal::None)
    return v;
  f = insertOf(x, y, sink.point, u, overlap);
  f.found.seat = Constraint::Found::Seat::Countersink;
  f.found.seatRadius = sink.face->radius;
  f.found.seatAngle = sink.face->halfAngle;
  return {};
}

// Opposed normals, one plane, and a common area that is more than an edge. On success `f` holds the mate,
// its direction x's outward normal.
Verdict testMate(const RecognitionPart& A, const WorldFace& x, const RecognitionPart& B, const WorldFace& y,
                 const RecognitionTolerances& tol, FoundConstraint& f, FaceGrids* grids = nullptr) {
  const double cosine = x.direction.dot(y.direction);
  if (cosine > -1.0 + 0.5 * tol.angle * tol.angle) {
    if (cosine > 1.0 - 0.5 * tol.angle * tol.angle) return {Refusal::SameWay, 0.0, tol.angle};
    return {Refusal::NotFacing, std::acos(std::clamp(-cosine, -1.0, 1.0)), tol.angle};
  }
  const double gap = std::abs(x.direction.dot(y.point - x.point));
  if (gap > tol.distance) return {Refusal::PlanesApart, gap, tol.distance};
  const double area = overlapArea(*A.solid, *x.face, A.pose, *B.solid, *y.face, B.pose, grids);
  const double smaller = std::min(x.face->area, y.face->area);
  if (!(area > tol.minOverlapRel * smaller)) return {Refusal::NoArea, area, tol.minOverlapRel * smaller};
  f = FoundConstraint{};
  f.type = Constraint::Type::Mate;
  f.point = x.point;
  f.direction = x.direction;
  f.found.overlap = area;
  f.found.fromSpline = x.face->fromSpline || y.face->fromSpline;
  return {};
}

FoundConstraint between(FoundConstraint f, std::size_t a, std::size_t b, const WorldFace& x, const WorldFace& y) {
  f.a = a;
  f.b = b;
  f.faceA = x.index;
  f.faceB = y.index;
  return f;
}

// A length or an angle as a person reads it: one decimal, more where that would round a refusal to zero.
std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, std::abs(value) >= 0.1 ? "%.1f" : "%.3f", value);
  return text;
}
std::string mm(double metres) { return number(metres * 1000.0) + " mm"; }
std::string degrees(double radians) { return number(radians * 180.0 / std::numbers::pi) + " deg"; }

std::string describe(const Verdict& v) {
  switch (v.refusal) {
    case Refusal::None: return {};
    case Refusal::BothHoles: return "both are holes";
    case Refusal::BothShafts: return "both are shafts";
    case Refusal::AxesAngle: return "the axes are " + degrees(v.value) + " apart";
    case Refusal::AxesApart: return "the axes are " + mm(v.value) + " apart";
    case Refusal::Interference:
      return "the shaft is " + mm(v.value) + " larger in radius than the bore: neither a thread modelled at its tap drill nor a press fit";
    case Refusal::TooLoose:
      return "the bore is " + mm(v.value) + " larger in radius than the shaft: more play than " + mm(v.limit);
    case Refusal::NoAxialOverlap:
      if (v.value > 0.0) return "the faces overlap by only " + mm(v.value) + " along the axis";
      return "the faces do not overlap along the axis" + (v.value < 0.0 ? " (" + mm(-v.value) + " between them)" : "");
    case Refusal::NotFacing: return "the planes are " + degrees(v.value) + " from facing each other";
    case Refusal::SameWay: return "the planes face the same way";
    case Refusal::PlanesApart: return "the planes are " + mm(v.value) + " apart";
    case Refusal::ConeAngles: return "the cones' half angles are " + degrees(v.value) + " apart";
    case Refusal::ConesApart: return "the cones stand " + mm(v.value) + " apart";
    case Refusal::NoArea:
      if (v.value > 0.0) return "the faces share only " + number(v.value * 1e6) + " mm² (they meet at an edge)";
      return "the faces share no area";
  }
  return {};
}

Eigen::Vector3d closestOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                  const Eigen::Vector3d& c) {
  // Ericson, Real-Time Collision Detection 5.1.5: by the Voronoi region of the triangle p lies in.
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + ab * (d1 / (d1 - d3));
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double denominator = va + vb + vc;
  if (denominator <= 0.0) return a;  // a degenerate triangle: its corner will do
  return a + ab * (vb / denominator) + ac * (vc / denominator);
}

// Distance from p to a face's triangles; infinite for a face without any.
double distanceToTriangles(const CadSolid& s, const CadFace& f, const Eigen::Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t t = f.firstTriangle; t < f.firstTriangle + f.triangleCount && t < s.mesh.triangles.size(); ++t) {
    const auto& tri = s.mesh.triangles[t];
    const auto corner = [&](int k) -> const Eigen::Vector3d* {
      const auto vi = static_cast<std::size_t>(tri[k]);
      return vi < s.mesh.vertices.size() ? &s.mesh.vertices[vi] : nullptr;
    };
    const Eigen::Vector3d *a = corner(0), *b = corner(1), *c = corner(2);
    if (a == nullptr || b == nullptr || c == nullptr) continue;
    best = std::min(best, (p - closestOnTriangle(p, *a, *b, *c)).norm());
  }
  return best;
}

// One constraint per pair of parts and axis (insert) or plane (mate): faces of one surface that a solid
// still has apart (a stepped shaft's two diameters in a stepped bore, two feet on one plane that the
// exporter left separate) add their overlap to the first, and an insert keeps its tightest fit.
std::vector<FoundConstraint> onePerContact(std::vector<FoundConstraint> found, const RecognitionTolerances& tol) {
  std::vector<FoundConstraint> out;
  // The constraints kept so far, per pair and kind.
  std::map<std::tuple<std::size_t, std::size_t, int>, std::vector<std::size_t>> byPair;
  for (FoundConstraint& f : found) {
    FoundConstraint* same = nullptr;
    auto& kept = byPair[{f.a, f.b, static_cast<int>(f.type)}];
    for (const std::size_t k : kept) {
      FoundConstraint& g = out[k];
      if (f.direction.cross(g.direction).norm() > tol.angle) continue;
      const Eigen::Vector3d rel = f.point - g.point;
      const double apart = f.type == Constraint::Type::Insert ? (rel - g.direction * g.direction.dot(rel)).norm()
                                                              : std::abs(g.direction.dot(rel));
      if (f.type == Constraint::Type::Mate && f.direction.dot(g.direction) < 0.0) continue;
      if (apart <= tol.distance) {
        same = &g;
        break;
      }
    }
    if (!same) {
      kept.push_back(out.size());
      out.push_back(std::move(f));
      continue;
    }
    const double overlap = same->found.overlap + f.found.overlap;
    // Two diameters on one axis (a head in a counterbore over its shank's hole): the larger bore is kept as
    // a counterbore's, which a seat under the head confirms (seatsInCounterbores).
    const double outer = std::max(f.found.partRadius, f.found.partnerRadius);
    const double before = std::max(same->found.partRadius, same->found.partnerRadius);
    const double stepped = std::abs(outer - before) > tol.distance ? std::max({outer, before, same->found.seatRadius}) : same->found.seatRadius;
    // The fit that holds: a designed interference (a counterbored head's play above a thread does not), else
    // the tightest.
    const auto interference = [](const FoundConstraint& x) { return x.found.fit != Constraint::Found::Fit::Clearance; };
    const bool holds = interference(f) != interference(*same) ? interference(f) : f.found.clearance < same->found.clearance;
    if (f.type == Constraint::Type::Insert && holds) {
      const Eigen::Vector3d point = same->point, direction = same->direction;
      *same = f;
      same->point = point;
      same->direction = direction;
    }
    same->found.overlap = overlap;
    same->found.fromSpline = same->found.fromSpline || f.found.fromSpline;
    if (f.type == Constraint::Type::Insert) same->found.seatRadius = stepped;
  }
  return out;
}

// A stepped insert is a head in a counterbore when the pair also has a seat across its axis (the head's
// underside on the counterbore's floor); otherwise it is a stepped fit and no counterbore.
void seatsInCounterbores(std::vector<FoundConstraint>& found, const RecognitionTolerances& tol) {
  const double parallel = std::cos(tol.angle);
  for (FoundConstraint& f : found) {
    if (f.type != Constraint::Type::Insert || f.found.seatRadius <= 0.0) continue;
    const bool seated = std::any_of(found.begin(), found.end(), [&](const FoundConstraint& m) {
      return m.type == Constraint::Type::Mate && m.a == f.a && m.b == f.b && std::abs(m.direction.dot(f.direction)) >= parallel;
    });
    if (seated) f.found.seat = Constraint::Found::Seat::Counterbore;
    else f.found.seatRadius = 0.0;
  }
}

// A countersunk head's seat is the seat of the screw's insert in that part, on that axis (its shank in the
// hole under the countersink); a seat with no such insert is the pair's insert itself, kept in the order
// recognizeConstraints gives (by pair).
void seatsInCountersinks(std::vector<FoundConstraint>& found, const std::vector<FoundConstraint>& seats,
                         const RecognitionTolerances& tol) {
  for (const FoundConstraint& s : seats) {
    const auto onAxis = [&](const FoundConstraint& f) {
      if (f.type != Constraint::Type::Insert || f.a != s.a || f.b != s.b || f.direction.cross(s.direction).norm() > tol.angle)
        return false;
      const Eigen::Vector3d rel = f.point - s.point;
      return (rel - s.direction * s.direction.dot(rel)).norm() <= tol.distance;
    };
    const auto insert = std::find_if(found.begin(), found.end(), onAxis);
    if (insert == found.end()) {
      const auto after = std::find_if(found.begin(), found.end(),
                                      [&](const FoundConstraint& f) { return std::pair(f.a, f.b) > std::pair(s.a, s.b); });
      found.insert(after, s);
    } else if (insert->found.seat != Constraint::Found::Seat::Countersink) {
      insert->found.seat = Constraint::Found::Seat::Countersink;
      insert->found.seatRadius = s.found.seatRadius;
      insert->found.seatAngle = s.found.seatAngle;
      insert->found.fromSpline = insert->found.fromSpline || s.found.fromSpline;
    }
  }
}

// Two mates of one pair whose planes face opposite ways hold one part's two parallel faces between two of
// the other's: a key in its keyway or in a hub's slot. They are one constraint, the first side kept with
// the width between the two and both areas.
void keysInSlots(std::vector<FoundConstraint>& found, const RecognitionTolerances& tol) {
  const double opposed = -std::cos(tol.angle);
  std::vector<bool> merged(found.size(), false);
  for (std::size_t i = 0; i < found.size(); ++i) {
    FoundConstraint& side = found[i];
    if (side.type != Constraint::Type::Mate || merged[i]) continue;
    for (std::size_t j = i + 1; j < found.size() && found[j].a == side.a && found[j].b == side.b; ++j) {
      const FoundConstraint& other = found[j];
      if (other.type != Constraint::Type::Mate || merged[j] || side.direction.dot(other.direction) > opposed) continue;
      side.found.keyWidth = std::abs(side.direction.dot(other.point - side.point));
      side.found.overlap += other.found.overlap;
      side.found.fromSpline = side.found.fromSpline || other.found.fromSpline;
      merged[j] = true;
      break;
    }
  }
  std::vector<FoundConstraint> kept;
  kept.reserve(found.size());
  for (std::size_t i = 0; i < found.size(); ++i)
    if (!merged[i]) kept.push_back(std::move(found[i]));
  found = std::move(kept);
}

}  // namespace

double coplanarOverlapArea(const CadSolid& a, const CadFace& fa, const Eigen::Isometry3d& poseA, const CadSolid& b,
                           const CadFace& fb, const Eigen::Isometry3d& poseB) {
  return overlapArea(a, fa, poseA, b, fb, poseB, nullptr);
}

namespace {

double overlapArea(const CadSolid& a, const CadFace& fa, const Eigen::Isometry3d& poseA, const CadSolid& b, const CadFace& fb,
                   const Eigen::Isometry3d& poseB, FaceGrids* grids) {
  const Eigen::Vector3d n = (poseA.linear() * fa.direction).normalized();
  const Eigen::Vector3d e1 = anyPerpendicular(n), e2 = n.cross(e1);
  const Eigen::Vector3d origin = poseA * fa.point;
  // The face with fewer triangles first; of the other only what meets its box, which leaves the area as it
  // is (a triangle outside that box meets none of the first face's).
  const bool aFirst = fa.triangleCount <= fb.triangleCount;
  const std::vector<Tri2> few = aFirst ? faceTriangles(a, fa, poseA, origin, e1, e2) : faceTriangles(b, fb, poseB, origin, e1, e2);
  Eigen::AlignedBox2d reach;
  for (const Tri2& t : few) reach.extend(t.box);
  if (reach.isEmpty()) return 0.0;
  // Of a large face only the triangles its grid finds under the small face (in the large one's frame).
  const CadSolid& large = aFirst ? b : a;
  const CadFace& largeFace = aFirst ? fb : fa;
  const Eigen::Isometry3d& largePose = aFirst ? poseB : poseA;
  std::optional<std::vector<std::size_t>> only;
  if (const FaceGrid* grid = grids ? grids->of(large, largeFace) : nullptr) {
    const CadSolid& small = aFirst ? a : b;
    const CadFace& smallFace = aFirst ? fa : fb;
    const Eigen::Isometry3d toLarge = largePose.inverse() * (aFirst ? poseA : poseB);
    Eigen::AlignedBox2d under;
    for (std::size_t t = smallFace.firstTriangle;
         t < smallFace.firstTriangle + smallFace.triangleCount && t < small.mesh.triangles.size(); ++t)
      for (int k = 0; k < 3; ++k) {
        const auto vi = static_cast<std::size_t>(small.mesh.triangles[t][k]);
        if (vi < small.mesh.vertices.size()) under.extend(grid->project(toLarge * small.mesh.vertices[vi]));
      }
    // Grown by far more than round-off, so that a triangle the box test below would keep is never missed.
    under.min().array() -= 1e-6;
    under.max().array() += 1e-6;
    only = grid->near(under);
  }
  const std::vector<Tri2> near = faceTriangles(large, largeFace, largePose, origin, e1, e2, &reach, only ? &*only : nullptr);
  double total = 0.0;
  for (const Tri2& x : few)
    for (const Tri2& y : near) {
      if (!x.box.intersects(y.box)) continue;
      const std::vector<P> common = clipConvex(x.corners, y.corners);
      if (common.size() >= 3) total += std::abs(g2::area(common));
    }
  return total;
}

// Candidate pairs of parts (index order) whose boxes, grown by `margin`, meet: a sweep along x.
std::vector<std::pair<std::size_t, std::size_t>> candidatePairs(const std::vector<RecognitionPart>& parts, double margin) {
  std::vector<Eigen::AlignedBox3d> boxes;
  for (const auto& p : parts) {
    Eigen::AlignedBox3d b = worldBox(p);
    if (!b.isEmpty()) {
      b.min().array() -= 0.5 * margin;
      b.max().array() += 0.5 * margin;
    }
    boxes.push_back(b);
  }
  std::vector<std::size_t> byX;
  for (std::size_t i = 0; i < parts.size(); ++i)
    if (!boxes[i].isEmpty()) byX.push_back(i);
  std::sort(byX.begin(), byX.end(), [&](std::size_t a, std::size_t b) { return boxes[a].min().x() < boxes[b].min().x(); });
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (std::size_t k = 0; k < byX.size(); ++k)
    for (std::size_t l = k + 1; l < byX.size() && boxes[byX[l]].min().x() <= boxes[byX[k]].max().x(); ++l)
      if (boxes[byX[k]].intersects(boxes[byX[l]])) pairs.emplace_back(std::minmax(byX[k], byX[l]));
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

}  // namespace

std::vector<NearMiss> nearMisses(const std::vector<RecognitionPart>& parts, const RecognitionTolerances& tol) {
  constexpr double kAngle = 0.0175;  // rad, about 1 degree
  constexpr double kApart = 0.5e-3;  // m
  std::vector<NearMiss> out;
  FaceGrids grids;
  const auto add = [&](std::size_t i, std::size_t j, const WorldFace& x, const WorldFace& y, Constraint::Type type, const Verdict& v) {
    out.push_back({i, j, x.index, y.index, type, describe(v), v.value, v.limit});
  };
  for (const auto& [i, j] : candidatePairs(parts, tol.distance + tol.maxClearance + kApart)) {
    const std::vector<WorldFace> ci = worldFaces(parts[i], CadFace::Surface::Cylinder), cj = worldFaces(parts[j], CadFace::Surface::Cylinder);
    for (const WorldFace& x : ci)
      for (const WorldFace& y : cj) {
        if (x.face->convex == y.face->convex || x.direction.cross(y.direction).norm() > kAngle) continue;
        const Eigen::Vector3d rel = y.point - x.point;
        const double apart = (rel - x.direction * x.direction.dot(rel)).norm();
        const double bore = x.face->convex ? y.face->radius : x.face->radius;
        if (apart > std::max(kApart, 0.1 * std::min(x.face->radius, y.face->radius))) continue;
        FoundConstraint f;
        const Verdict v = testInsert(x, y, tol, f);
        // A shaft larger than the bore by more than a few percent is a head over its hole, not a fit; and only
        // where the two faces overlap along the axis.
        const auto overlapping = [&] {
          const WorldFace& shaft = x.face->convex ? x : y;
          const WorldFace& hole = x.face->convex ? y : x;
          const Eigen::Vector3d u = hole.direction;
          const double shift = u.dot(shaft.point - hole.point), sign = shaft.direction.dot(u) >= 0.0 ? 1.0 : -1.0;
          const double s0 = std::min(shift + sign * shaft.axialMin, shift + sign * shaft.axialMax);
          const double s1 = std::max(shift + sign * shaft.axialMin, shift + sign * shaft.axialMax);
          return std::min(s1, hole.axialMax) - std::max(s0, hole.axialMin) > tol.distance;
        };
        const bool near = v.refusal == Refusal::AxesAngle || v.refusal == Refusal::AxesApart ||
                          (v.refusal == Refusal::Interference && v.value <= 0.15 * bore && overlapping()) ||
                          (v.refusal == Refusal::TooLoose && v.value <= 2.0 * v.limit) ||
                          (v.refusal == Refusal::NoAxialOverlap && v.value > -1e-3);
        if (near) add(i, j, x, y, Constraint::Type::Insert, v);
      }
    const std::vector<WorldFace> pi = worldFaces(parts[i], CadFace::Surface::Plane), pj = worldFaces(parts[j], CadFace::Surface::Plane);
    for (const WorldFace& x : pi)
      for (const WorldFace& y : pj) {
        if (x.direction.dot(y.direction) > -std::cos(kAngle) || std::abs(x.direction.dot(y.point - x.point)) > kApart) continue;
        FoundConstraint f;
        const Verdict v = testMate(parts[i], x, parts[j], y, tol, f, &grids);
        if (v.refusal != Refusal::NotFacing && v.refusal != Refusal::PlanesApart) continue;
        // Over each other by more than an edge: their faces projected into x's plane share area.
        const double area = overlapArea(*parts[i].solid, *x.face, parts[i].pose, *parts[j].solid, *y.face, parts[j].pose, &grids);
        if (area > tol.minOverlapRel * std::min(x.face->area, y.face->area)) add(i, j, x, y, Constraint::Type::Mate, v);
      }
  }
  return out;
}

std::vector<NearMiss> nearMisses(const Assembly& assembly) {
  if (assembly.cadFile.empty()) return {};
  const std::vector<Eigen::Isometry3d> poses = collision::assembledPoses(assembly);
  std::vector<RecognitionPart> parts;
  for (const Part& p : assembly.parts) parts.push_back({p.cad, poses[p.id]});
  return nearMisses(parts);
}

std::vector<FoundConstraint> recognizeConstraints(const std::vector<RecognitionPart>& parts, const RecognitionTolerances& tol,
                                                  const PairProgress& progress) {
  std::vector<FoundConstraint> out;
  // Candidate pairs from a sweep over the parts' boxes, then in index order, so the constraints come out in
  // the order a test of every pair gives.
  const std::vector<std::pair<std::size_t, std::size_t>> pairs = candidatePairs(parts, tol.distance + tol.maxClearance);

  // Each part's faces in the world once, not once per partner (the base meets every part).
  std::vector<std::vector<WorldFace>> cylinders(parts.size()), planes(parts.size()), cones(parts.size());
  for (std::size_t i = 0; i < parts.size(); ++i) {
    cylinders[i] = worldFaces(parts[i], CadFace::Surface::Cylinder);
    planes[i] = worldFaces(parts[i], CadFace::Surface::Plane);
    cones[i] = worldFaces(parts[i], CadFace::Surface::Cone);
  }
  std::vector<FoundConstraint> seats;
  FaceGrids grids;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const auto [i, j] = pairs[k];
    if (progress && !progress(static_cast<double>(k) / static_cast<double>(pairs.size()), i, j)) throw LoadCancelled();
    FoundConstraint f;
    for (const WorldFace& x : cylinders[i])
      for (const WorldFace& y : cylinders[j])
        if (testInsert(x, y, tol, f).refusal == Refusal::None) out.push_back(between(f, i, j, x, y));
    for (const WorldFace& x : planes[i])
      for (const WorldFace& y : planes[j])
        if (testMate(parts[i], x, parts[j], y, tol, f, &grids).refusal == Refusal::None) out.push_back(between(f, i, j, x, y));
    for (const WorldFace& x : cones[i])
      for (const WorldFace& y : cones[j])
        if (testCountersink(x, y, tol, f).refusal == Refusal::None) seats.push_back(between(f, i, j, x, y));
  }
  std::vector<FoundConstraint> found = onePerContact(std::move(out), tol);
  seatsInCounterbores(found, tol);
  seatsInCountersinks(found, onePerContact(std::move(seats), tol), tol);
  keysInSlots(found, tol);
  return found;
}

std::optional<std::size_t> faceAt(const CadSolid& s, const Eigen::Vector3d& point, double tolerance) {
  std::optional<std::size_t> best;
  double bestScore = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < s.faces.size(); ++i) {
    const CadFace& f = s.faces[i];
    const double onMesh = distanceToTriangles(s, f, point);
    double onSurface = onMesh;
    if (f.surface == CadFace::Surface::Plane) {
      onSurface = std::abs(f.direction.normalized().dot(point - f.point));
    } else if (f.surface == CadFace::Surface::Cylinder) {
      const Eigen::Vector3d u = f.direction.normalized(), rel = point - f.point;
      const double t = u.dot(rel);
      if (t < f.axialMin - tolerance || t > f.axialMax + tolerance) continue;
      onSurface = std::abs((rel - u * t).norm() - f.radius);
    } else if (f.surface == CadFace::Surface::Cone) {
      const Eigen::Vector3d u = f.direction.normalized(), rel = point - f.point;
      const double t = u.dot(rel);
      if (t < f.axialMin - tolerance || t > f.axialMax + tolerance) continue;
      onSurface = std::abs((rel - u * t).norm() * std::cos(f.halfAngle) - t * std::sin(f.halfAngle));
    }
    if (!(onSurface <= tolerance)) continue;
    // A plane or a cylinder goes on where its face ends: where the face has triangles the point must be near
    // them, which also tells coplanar faces and the halves of a cylinder split at its seam apart.
    if (f.triangleCount > 0 && !(onMesh <= tolerance)) continue;
    const double score = onSurface + (f.triangleCount > 0 ? onMesh : 0.0);
    if (score < bestScore) {
      bestScore = score;
      best = i;
    }
  }
  return best;
}

FacePairResult constraintFromFaces(const std::vector<RecognitionPart>& parts, std::size_t a, std::size_t faceA, std::size_t b,
                                   std::size_t faceB, const RecognitionTolerances& tol) {
  if (a == b) return {std::nullopt, "both faces are on the same part"};
  for (const auto& [part, face] : {std::pair{a, faceA}, std::pair{b, faceB}})
    if (part >= parts.size() || !parts[part].solid || face >= parts[part].solid->faces.size())
      return {std::nullopt, "a face that is not on the part's CAD solid"};
  const WorldFace x = worldFace(parts[a], faceA), y = worldFace(parts[b], faceB);
  const auto both = [&](CadFace::Surface kind) { return x.face->surface == kind && y.face->surface == kind; };
  if (!both(CadFace::Surface::Cylinder) && !both(CadFace::Surface::Plane) && !both(CadFace::Surface::Cone))
    return {std::nullopt, "the two faces are not both cylinders, both cones or both planes"};
  FoundConstraint f;
  const Verdict v = both(CadFace::Surface::Cylinder) ? testInsert(x, y, tol, f)
                    : both(CadFace::Surface::Cone)   ? testCountersink(x, y, tol, f)
                                                     : testMate(parts[a], x, parts[b], y, tol, f);
  if (v.refusal != Refusal::None) return {std::nullopt, describe(v)};
  return {between(f, a, b, x, y), {}};
}

std::vector<Constraint> constraintsFromFound(const std::vector<FoundConstraint>& found, const std::vector<Part>& parts,
                                             PartId base, const std::vector<Eigen::Isometry3d>& finalPoses,
                                             const std::vector<std::pair<PartId, PartId>>& contacts,
                                             const std::vector<std::pair<PartId, PartId>>& first) {
  const std::size_t n = parts.size();
  // Hops from the base over the contact graph: the base goes first, then what touches it, and so on.
  std::vector<std::vector<std::size_t>> next(n);
  const auto touch = [&](std::size_t x, std::size_t y) {
    next[x].push_back(y);
    next[y].push_back(x);
  };
  for (const FoundConstraint& f : found) touch(f.a, f.b);
  for (const auto& [x, y] : contacts)
    if (x < n && y < n) touch(x, y);
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
  // True when `x` is assembled before `y`, so `x` is the partner: as the geometry decided, else the base
  // first, the part nearer the base, the shaft before what goes onto it (a nut onto its bolt), the lower.
  const std::set<std::pair<PartId, PartId>> decided(first.begin(), first.end());
  const auto before = [&](std::size_t x, std::size_t y, const FoundConstraint& f) {
    if (decided.count({x, y})) return true;
    if (decided.count({y, x})) return false;
    if (x == base || y == base) return x == base;
    if (hops[x] != hops[y]) return hops[x] < hops[y];
    if (f.type == Constraint::Type::Insert && parts[f.a].cad && parts[f.b].cad && f.faceA < parts[f.a].cad->faces.size() &&
        f.faceB < parts[f.b].cad->faces.size()) {
      const bool aShaft = parts[f.a].cad->faces[f.faceA].convex, bShaft = parts[f.b].cad->faces[f.faceB].convex;
      if (aShaft != bShaft) return (x == f.a) == aShaft;
    }
    const double eps = 1e-6;
    if (std::abs(lowest[x] - lowest[y]) > eps) return lowest[x] < lowest[y];
    if (parts[x].mass.mass != parts[y].mass.mass) return parts[x].mass.mass > parts[y].mass.mass;
    return x < y;
  };

  std::vector<Constraint> out;
  std::map<std::tuple<std::size_t, std::size_t, int>, int> seen;
  for (const FoundConstraint& f : found) {
    const bool aFirst = before(f.a, f.b, f);
    const std::size_t part = aFirst ? f.b : f.a, partner = aFirst ? f.a : f.b;
    // Several faces of one pair can give the same kind (a stepped shaft): each is kept, numbered.
    const int count = ++seen[{part, partner, static_cast<int>(f.type)}];
    const Eigen::Isometry3d toPart = finalPoses[part].inverse(), toPartner = finalPoses[partner].inverse();
    Constraint c;
    c.type = f.type;
    c.part = part;
    if (partner != base) c.partner = partner;
    c.found = f.found;
    // The found radii are face a's then face b's; when a is the partner, the part's is b's.
    if (aFirst && f.type == Constraint::Type::Insert) std::swap(c.found->partRadius, c.found->partnerRadius);
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
