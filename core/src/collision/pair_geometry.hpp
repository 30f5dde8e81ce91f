#pragma once
// Triangle-pair geometry for the filter modes (private to the collision sources). Everything is in one
// frame (the first object's).
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>

namespace vaw::collision::pairgeom {

using V = Eigen::Vector3d;
using Tri = std::array<V, 3>;

inline V unitNormal(const Tri& t) {
  const V n = (t[1] - t[0]).cross(t[2] - t[0]);
  const double len = n.norm();
  return len > 0.0 ? V(n / len) : V::Zero();
}

// Largest distance of t's corners from the plane through p with unit normal n.
inline double maxPlaneDistance(const Tri& t, const V& n, const V& p) {
  double d = 0.0;
  for (const V& x : t) d = std::max(d, std::abs(n.dot(x - p)));
  return d;
}

// Parallel (either orientation) within cosAngle and each triangle within `distance` of the other's plane.
inline bool coplanar(const Tri& a, const V& na, const Tri& b, const V& nb, double cosAngle, double distance) {
  if (std::abs(na.dot(nb)) < cosAngle) return false;
  return maxPlaneDistance(b, na, a[0]) <= distance && maxPlaneDistance(a, nb, b[0]) <= distance;
}

// The part of triangle t on the plane n.x = c, as its two extreme points along `dir`. False when t does
// not reach the plane.
inline bool planeCut(const Tri& t, const V& n, double c, const V& dir, V& lo, V& hi) {
  constexpr double eps = 1e-13;
  double s[3];
  for (int i = 0; i < 3; ++i) s[i] = n.dot(t[static_cast<std::size_t>(i)]) - c;
  V pts[6];
  int count = 0;
  for (int i = 0; i < 3; ++i)
    if (std::abs(s[i]) <= eps) pts[count++] = t[static_cast<std::size_t>(i)];
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    if ((s[i] > eps && s[j] < -eps) || (s[i] < -eps && s[j] > eps)) {
      const V& a = t[static_cast<std::size_t>(i)];
      const V& b = t[static_cast<std::size_t>(j)];
      pts[count++] = a + (b - a) * (s[i] / (s[i] - s[j]));
    }
  }
  if (count == 0) return false;
  lo = hi = pts[0];
  double tlo = dir.dot(pts[0]), thi = tlo;
  for (int k = 1; k < count; ++k) {
    const double tk = dir.dot(pts[k]);
    if (tk < tlo) { tlo = tk; lo = pts[k]; }
    if (tk > thi) { thi = tk; hi = pts[k]; }
  }
  return true;
}

struct Crossing {
  bool crosses = false;     // the triangles' intersection is a segment or point
  double penetration = 0.0; // m, see below
  V point = V::Zero();      // middle of the intersection
  // True when a is the shallower side at the deepest point of I: the depth is then a's, measured along
  // b's normal (else b's, along a's normal). Decides which tessellation error can explain it.
  bool aBinding = true;
};

// How deeply two intersecting triangles pass through each other, local to their intersection I (a
// segment on the line where their planes meet): sin(theta) * max over x in I of min(d_a(x), d_b(x)), where
// d(x) is the in-plane distance from x to that triangle's boundary and theta the angle between the planes.
// Zero when I lies on either triangle's boundary (faces resting on faces, edges on faces, shared edges
// and corners of a coincident tessellation); about the normal depth of the deeper side otherwise (a block
// pushed d into a wall gives d), and never more than the corners of either triangle reach behind the
// other's plane. Coplanar triangles give zero.
//
// Only the edges on each triangle's face outline count as its boundary (edgesA/B, bit k: edge from corner k
// to k+1): a face split into small triangles is one face, and the depth into it is not capped by the
// triangles' size. A triangle with no outline edge counts as extending as far as its longest edge.
inline Crossing crossing(const Tri& a, const V& na, unsigned edgesA, const Tri& b, const V& nb, unsigned edgesB) {
  Crossing r;
  const V dirRaw = na.cross(nb);
  const double sinTheta = dirRaw.norm();
  if (sinTheta < 1e-12) return r;
  const V dir = dirRaw / sinTheta;
  V a0, a1, b0, b1;
  if (!planeCut(a, nb, nb.dot(b[0]), dir, a0, a1)) return r;
  if (!planeCut(b, na, na.dot(a[0]), dir, b0, b1)) return r;
  const double ta0 = dir.dot(a0), ta1 = dir.dot(a1), tb0 = dir.dot(b0), tb1 = dir.dot(b1);
  const double lo = std::max(ta0, tb0), hi = std::min(ta1, tb1);
  if (lo > hi + 1e-13) return r;
  r.crosses = true;
  // Points of I: x(t) = a0 + (t - ta0) dir (a0 is on both planes up to rounding).
  const V x0 = a0 + (lo - ta0) * dir;
  const V x1 = a0 + (std::max(lo, hi) - ta0) * dir;
  r.point = 0.5 * (x0 + x1);
  // d(x) = min over the edges of the in-plane distance to the edge's line: 6 functions linear in
  // u in [0, 1] along I; their lower envelope is concave, so its maximum is at an end or where two meet.
  double c0[8], c1[8];
  int m = 0;
  auto addEdges = [&](const Tri& t, const V& n, unsigned edges) {
    double longest = 0.0;
    for (int i = 0; i < 3; ++i) longest = std::max(longest, (t[static_cast<std::size_t>((i + 1) % 3)] - t[static_cast<std::size_t>(i)]).norm());
    c0[m] = c1[m] = longest;  // the cap
    ++m;
    for (int i = 0; i < 3; ++i) {
      if (!(edges & (1u << i))) continue;
      const V& p = t[static_cast<std::size_t>(i)];
      const V& q = t[static_cast<std::size_t>((i + 1) % 3)];
      V inward = n.cross(q - p);
      const double len = inward.norm();
      if (len <= 0.0) continue;
      inward /= len;
      c0[m] = inward.dot(x0 - p);
      c1[m] = inward.dot(x1 - p);
      ++m;
    }
  };
  addEdges(a, na, edgesA);
  addEdges(b, nb, edgesB);
  auto envelope = [&](double u, int from, int to) {
    double f = 1e300;
    for (int k = from; k < to; ++k) f = std::min(f, c0[k] + u * (c1[k] - c0[k]));
    return f;
  };
  double best = -1e300, bestU = 0.0;
  auto consider = [&](double u) {
    const double f = envelope(u, 0, m);
    if (f > best) {
      best = f;
      bestU = u;
    }
  };
  consider(0.0);
  consider(1.0);
  for (int i = 0; i < m; ++i)
    for (int j = i + 1; j < m; ++j) {
      const double si = c1[i] - c0[i], sj = c1[j] - c0[j];
      if (std::abs(si - sj) < 1e-300) continue;
      const double u = (c0[j] - c0[i]) / (si - sj);
      if (u > 0.0 && u < 1.0) consider(u);
    }
  // Never more than either triangle's corners reach behind the other's plane (the estimate above can
  // overshoot when a triangle has no outline edge near I, e.g. a corner of a finely split face).
  double behindA = 0.0, behindB = 0.0;
  for (const V& x : a) behindA = std::max(behindA, -nb.dot(x - b[0]));
  for (const V& x : b) behindB = std::max(behindB, -na.dot(x - a[0]));
  r.penetration = std::min({std::max(0.0, best) * sinTheta, behindA, behindB});
  // Which triangle's depth that is: at the deepest point, each triangle's extent beyond I measured
  // perpendicular to I, into the other's back side (a ray cast inside the triangle).
  const V xs = x0 + bestU * (x1 - x0);
  auto extent = [&](const Tri& t, const V& n, unsigned edges, const V& otherNormal) {
    V w = n.cross(dir);
    if (otherNormal.dot(w) > 0.0) w = -w;
    double e = 1e300;
    for (int i = 0; i < 3; ++i) {
      if (!(edges & (1u << i))) continue;
      const V& p = t[static_cast<std::size_t>(i)];
      const V& q = t[static_cast<std::size_t>((i + 1) % 3)];
      V inward = n.cross(q - p);
      const double len = inward.norm();
      if (len <= 0.0) continue;
      inward /= len;
      const double rate = inward.dot(w);
      if (rate < -1e-15) e = std::min(e, std::max(0.0, inward.dot(xs - p)) / -rate);
    }
    return e;
  };
  r.aBinding = extent(a, na, edgesA, nb) <= extent(b, nb, edgesB, na);
  return r;
}

}  // namespace vaw::collision::pairgeom
