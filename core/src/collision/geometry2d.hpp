#pragma once
// Small 2-D helpers for outlines and support polygons (private to the collision sources).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

namespace vaw::collision::geom2 {

using P = Eigen::Vector2d;

// A unit vector perpendicular to n, always the same one for the same n: the first axis of the 2-D frame
// in which a plane's outline is drawn.
inline Eigen::Vector3d perpendicular(const Eigen::Vector3d& n) {
  const Eigen::Vector3d helper = std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return n.cross(helper).normalized();
}

inline double cross(const P& a, const P& b) { return a.x() * b.y() - a.y() * b.x(); }

inline double distanceToSegment(const P& p, const P& a, const P& b) {
  const P ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

// Drops vertices of a closed loop that lie on the segment between their neighbours (within `eps`), so
// a finely tessellated straight edge becomes one segment.
inline std::vector<P> mergeCollinear(std::vector<P> loop, double eps) {
  bool changed = true;
  while (changed && loop.size() > 3) {
    changed = false;
    std::vector<P> kept;
    kept.reserve(loop.size());
    const std::size_t n = loop.size();
    for (std::size_t i = 0; i < n; ++i) {
      const P& prev = kept.empty() ? loop[(i + n - 1) % n] : kept.back();
      const P& cur = loop[i];
      const P& next = loop[(i + 1) % n];
      const bool between = (cur - prev).dot(next - cur) > 0.0;
      if (between && distanceToSegment(cur, prev, next) <= eps) {
        changed = true;
        continue;
      }
      kept.push_back(cur);
    }
    if (kept.size() < 3) break;
    loop = std::move(kept);
  }
  return loop;
}

// Andrew's monotone chain; counter-clockwise, no repeated first point, collinear points dropped.
inline std::vector<P> convexHull(std::vector<P> pts) {
  std::sort(pts.begin(), pts.end(), [](const P& a, const P& b) { return a.x() != b.x() ? a.x() < b.x() : a.y() < b.y(); });
  pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
  if (pts.size() < 3) return pts;
  std::vector<P> h(2 * pts.size());
  std::size_t k = 0;
  for (const P& p : pts) {
    while (k >= 2 && cross(h[k - 1] - h[k - 2], p - h[k - 2]) <= 0.0) --k;
    h[k++] = p;
  }
  for (std::size_t i = pts.size() - 1, t = k + 1; i-- > 0;) {
    const P& p = pts[i];
    while (k >= t && cross(h[k - 1] - h[k - 2], p - h[k - 2]) <= 0.0) --k;
    h[k++] = p;
  }
  h.resize(k - 1);
  return h;
}

inline double area(const std::vector<P>& poly) {
  double a = 0.0;
  for (std::size_t i = 0; i < poly.size(); ++i) a += cross(poly[i], poly[(i + 1) % poly.size()]);
  return 0.5 * a;
}

// Signed distance from p to a convex counter-clockwise polygon: positive inside. A hull of one or two
// points (a degenerate contact) gives minus the distance to that point or segment.
inline double signedDistanceConvex(const P& p, const std::vector<P>& hull) {
  if (hull.empty()) return -1e300;
  if (hull.size() == 1) return -(p - hull[0]).norm();
  if (hull.size() == 2) return -distanceToSegment(p, hull[0], hull[1]);
  bool inside = true;
  double dmin = 1e300;
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const P& a = hull[i];
    const P& b = hull[(i + 1) % hull.size()];
    if (cross(b - a, p - a) < 0.0) inside = false;
    dmin = std::min(dmin, distanceToSegment(p, a, b));
  }
  return inside ? dmin : -dmin;
}

struct Segment { P a, b; };

// Even-odd rule over a set of segments (the boundary loops of a region with holes).
inline bool insideRegion(const P& p, const std::vector<Segment>& edges) {
  bool in = false;
  for (const Segment& s : edges) {
    const P& a = s.a;
    const P& b = s.b;
    if ((a.y() > p.y()) != (b.y() > p.y())) {
      const double x = a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
      if (p.x() < x) in = !in;
    }
  }
  return in;
}

inline double distanceToEdges(const P& p, const std::vector<Segment>& edges) {
  double d = 1e300;
  for (const Segment& s : edges) d = std::min(d, distanceToSegment(p, s.a, s.b));
  return d;
}

// Proper or touching intersection point of two segments; nothing for parallel segments (their shared
// endpoints are found by the inside tests).
inline std::optional<P> intersect(const Segment& s, const Segment& t) {
  const P r = s.b - s.a, q = t.b - t.a;
  const double den = cross(r, q);
  if (std::abs(den) <= 1e-300) return std::nullopt;
  const P w = t.a - s.a;
  const double u = cross(w, q) / den, v = cross(w, r) / den;
  if (u < 0.0 || u > 1.0 || v < 0.0 || v > 1.0) return std::nullopt;
  return s.a + u * r;
}

struct Box {
  P lo{1e300, 1e300}, hi{-1e300, -1e300};
  void extend(const P& p) { lo = lo.cwiseMin(p); hi = hi.cwiseMax(p); }
  [[nodiscard]] bool empty() const { return lo.x() > hi.x(); }
  [[nodiscard]] Box inflated(double d) const { return {(lo.array() - d).matrix(), (hi.array() + d).matrix()}; }
  [[nodiscard]] bool overlaps(const Box& o) const {
    return !(o.lo.x() > hi.x() || o.hi.x() < lo.x() || o.lo.y() > hi.y() || o.hi.y() < lo.y());
  }
  [[nodiscard]] bool contains(const P& p) const {
    return p.x() >= lo.x() && p.x() <= hi.x() && p.y() >= lo.y() && p.y() <= hi.y();
  }
};

inline Box boxOf(const Segment& s) {
  Box b;
  b.extend(s.a);
  b.extend(s.b);
  return b;
}

}  // namespace vaw::collision::geom2
