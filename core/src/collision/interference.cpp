#include "vaw/collision/interference.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "vaw/collision/collision_world.hpp"

namespace vaw::collision {

std::string_view name(Interference::Kind k) {
  switch (k) {
    case Interference::Kind::Contact: return "contact";
    case Interference::Kind::Threaded: return "threaded";
    case Interference::Kind::Press: return "press";
    case Interference::Kind::Clash: return "clash";
  }
  return "?";
}

std::vector<Eigen::Isometry3d> assembledPoses(const Assembly& a) {
  std::vector<Eigen::Isometry3d> poses;
  for (const Part& p : a.parts) poses.push_back(p.finalPose.value_or(p.pose));
  return poses;
}

namespace {

// A mesh's triangles in the world, with their boxes: what the lines below are cut with.
struct Solid {
  std::vector<std::array<Eigen::Vector3d, 3>> triangles;
  std::vector<Eigen::AlignedBox3d> boxes;
};

Solid worldSolid(const TriMesh& mesh, const Eigen::Isometry3d& pose) {
  Solid s;
  for (const auto& t : mesh.triangles) {
    std::array<Eigen::Vector3d, 3> w{pose * mesh.vertices[static_cast<std::size_t>(t[0])], pose * mesh.vertices[static_cast<std::size_t>(t[1])],
                                     pose * mesh.vertices[static_cast<std::size_t>(t[2])]};
    Eigen::AlignedBox3d b;
    for (const auto& v : w) b.extend(v);
    s.triangles.push_back(w);
    s.boxes.push_back(b);
  }
  return s;
}

// The triangles a line along axis k through the box can meet: those over the box's other two sides, however
// far along k (a line must see every crossing of the solid to tell inside from outside).
Solid alongAxis(const Solid& s, const Eigen::AlignedBox3d& box, int k) {
  const int u = (k + 1) % 3, v = (k + 2) % 3;
  Solid out;
  for (std::size_t i = 0; i < s.triangles.size(); ++i) {
    const Eigen::AlignedBox3d& b = s.boxes[i];
    if (b.max()[u] < box.min()[u] || b.min()[u] > box.max()[u] || b.max()[v] < box.min()[v] || b.min()[v] > box.max()[v]) continue;
    out.triangles.push_back(s.triangles[i]);
    out.boxes.push_back(b);
  }
  return out;
}

// Crossings of the line through `p` along axis `k` with the solid's triangles, sorted.
std::vector<double> crossings(const Solid& s, const Eigen::Vector3d& p, int k) {
  const int u = (k + 1) % 3, v = (k + 2) % 3;
  std::vector<double> out;
  for (const auto& t : s.triangles) {
    // The line hits the triangle where (u, v) lies inside its projection: barycentric in the (u, v) plane.
    const double x0 = t[0][u] - p[u], y0 = t[0][v] - p[v], x1 = t[1][u] - p[u], y1 = t[1][v] - p[v], x2 = t[2][u] - p[u], y2 = t[2][v] - p[v];
    const double w0 = x1 * y2 - x2 * y1, w1 = x2 * y0 - x0 * y2, w2 = x0 * y1 - x1 * y0;
    if (!((w0 >= 0 && w1 >= 0 && w2 >= 0) || (w0 <= 0 && w1 <= 0 && w2 <= 0))) continue;
    const double sum = w0 + w1 + w2;
    if (sum == 0.0) continue;  // edge-on
    out.push_back((w0 * t[0][k] + w1 * t[1][k] + w2 * t[2][k]) / sum);
  }
  std::sort(out.begin(), out.end());
  return out;
}

struct Overlap {
  double volume = 0.0, longest = 0.0;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
};

// The common volume of two solids by lines along axis k through a grid of n x n over the box's other two
// sides: each line's stretches inside both, summed times the cell's area.
Overlap overlapAlong(const Solid& allA, const Solid& allB, const Eigen::AlignedBox3d& box, int k, int n) {
  const int u = (k + 1) % 3, v = (k + 2) % 3;
  const Solid a = alongAxis(allA, box, k), b = alongAxis(allB, box, k);
  const Eigen::Vector3d size = box.sizes();
  const double du = size[u] / n, dv = size[v] / n;
  Overlap o;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      // Off the cell's centre by an irrational fraction: CAD geometry sits on round numbers, and a line
      // through a vertex or along an edge would count one crossing twice.
      Eigen::Vector3d p = box.min();
      p[u] += (i + 0.5 + 0.0618034) * du;
      p[v] += (j + 0.5 + 0.0414214) * dv;
      const std::vector<double> ca = crossings(a, p, k), cb = crossings(b, p, k);
      for (std::size_t x = 0; x + 1 < ca.size(); x += 2)
        for (std::size_t y = 0; y + 1 < cb.size(); y += 2) {
          const double lo = std::max({ca[x], cb[y], box.min()[k]}), hi = std::min({ca[x + 1], cb[y + 1], box.max()[k]});
          if (hi <= lo) continue;
          o.volume += (hi - lo) * du * dv;
          o.longest = std::max(o.longest, hi - lo);
          Eigen::Vector3d mid = p;
          mid[k] = 0.5 * (lo + hi);
          o.moment += mid * (hi - lo) * du * dv;
        }
    }
  return o;
}

// A clash measured on the meshes: the volume along the axis that sees it best (the mean of three would mix
// their errors), the depth as the least, over the three axes, of the longest stretch along it.
void measureClash(Interference& r, const TriMesh& ma, const Eigen::Isometry3d& pa, const TriMesh& mb, const Eigen::Isometry3d& pb,
                  const Eigen::AlignedBox3d& common) {
  const Solid a = worldSolid(ma, pa), b = worldSolid(mb, pb);
  constexpr int kLines = 64;
  double depth = std::numeric_limits<double>::infinity();
  Overlap best;
  for (int k = 0; k < 3; ++k) {
    const Overlap o = overlapAlong(a, b, common, k, kLines);
    if (o.longest < depth) {
      depth = o.longest;
      r.direction = Eigen::Vector3d::Unit(k);
    }
    if (o.volume > best.volume) best = o;
  }
  r.volume = best.volume;
  r.depth = std::isfinite(depth) ? depth : 0.0;
  r.where = best.volume > 0.0 ? Eigen::Vector3d(best.moment / best.volume) : common.center();
}

}  // namespace

std::vector<Interference> interferences(const Assembly& assembly, const std::vector<Eigen::Isometry3d>& poses, const PairProgress& progress) {
  std::vector<Interference> out;
  if (poses.size() != assembly.parts.size()) return out;
  CollisionWorld world(assembly);
  for (PartId p = 0; p < assembly.parts.size(); ++p) world.setPose(ObjectId::part(p), poses[p]);
  std::vector<std::pair<PartId, PartId>> pairs;
  for (PartId p = 0; p < assembly.parts.size(); ++p) {
    Eigen::AlignedBox3d box = world.worldBounds(ObjectId::part(p));
    if (box.isEmpty()) continue;
    box.min().array() -= world.tolerances().distance;
    box.max().array() += world.tolerances().distance;
    for (const ObjectId& o : world.near(box, ObjectId::part(p)))
      if (o.kind == ObjectId::Kind::Part && o.index > p) pairs.emplace_back(p, o.index);
  }
  std::sort(pairs.begin(), pairs.end());
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const auto [p, q] = pairs[k];
    if (progress && !progress(static_cast<double>(k) / static_cast<double>(pairs.size()), p, q)) throw LoadCancelled();
    QueryOptions any;
    any.stopAtFirst = true;
    if (world.query(ObjectId::part(p), ObjectId::part(q), any).contacts.empty()) continue;
    Interference r;
    r.a = p;
    r.b = q;
    QueryOptions deep;
    deep.dropTouching = true;
    deep.stopAtFirst = true;
    deep.skipDesigned = true;
    const bool clash = !world.query(ObjectId::part(p), ObjectId::part(q), deep).contacts.empty();
    // The designed fits between the two (a screw may hold both a thread and a head's seat in one part).
    const Constraint* designed = nullptr;
    for (const Constraint& c : assembly.constraints) {
      const PartId partner = c.partner.value_or(assembly.base.value_or(c.part));
      const bool between = (c.part == p && partner == q) || (c.part == q && partner == p);
      if (between && c.type == Constraint::Type::Insert && c.found && c.found->fit != Constraint::Found::Fit::Clearance) designed = &c;
    }
    if (clash) {
      const Eigen::AlignedBox3d common = world.worldBounds(ObjectId::part(p)).intersection(world.worldBounds(ObjectId::part(q)));
      measureClash(r, *assembly.parts[p].mesh, poses[p], *assembly.parts[q].mesh, poses[q], common);
      // Surfaces that cross without sharing measurable volume (facets of two tessellations of one
      // surface, a rim on a face) only touch.
      const double tol = world.tolerances().distance;
      r.kind = r.depth > tol && r.volume > tol * tol * tol ? Interference::Kind::Clash : Interference::Kind::Contact;
      if (r.kind == Interference::Kind::Contact) {
        r = Interference{};
        r.a = p;
        r.b = q;
      }
    } else if (designed) {
      const Constraint::Found& f = *designed->found;
      r.kind = f.fit == Constraint::Found::Fit::Threaded ? Interference::Kind::Threaded : Interference::Kind::Press;
      r.thread = f.thread;
      const double R = std::max(f.partRadius, f.partnerRadius), rb = std::min(f.partRadius, f.partnerRadius);
      r.volume = std::numbers::pi * (R * R - rb * rb) * f.overlap;
      r.depth = R - rb;
      const PartId partner = designed->partner.value_or(*assembly.base);
      const Eigen::Isometry3d& at = poses[partner];
      r.direction = (at.linear() * designed->baseAxis.direction).normalized();
      // The middle of the band: on the axis, halfway along the shaft's stretch inside the bore.
      const Eigen::Vector3d onAxis = at * designed->baseAxis.point;
      const Eigen::AlignedBox3d both = world.worldBounds(ObjectId::part(p)).intersection(world.worldBounds(ObjectId::part(q)));
      r.where = onAxis + r.direction * r.direction.dot(both.center() - onAxis);
    } else {
      r.kind = Interference::Kind::Contact;
    }
    out.push_back(std::move(r));
  }
  std::stable_sort(out.begin(), out.end(), [](const Interference& x, const Interference& y) {
    const auto rank = [](Interference::Kind k) {
      switch (k) {
        case Interference::Kind::Clash: return 0;
        case Interference::Kind::Threaded: return 1;
        case Interference::Kind::Press: return 2;
        case Interference::Kind::Contact: return 3;
      }
      return 4;
    };
    return rank(x.kind) < rank(y.kind);
  });
  return out;
}

}  // namespace vaw::collision
