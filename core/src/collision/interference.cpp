#include "vaw/collision/interference.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>

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

// The overlap of two solids seen by lines along axis k through an n x n grid over the box's other two sides
// (u = k + 1, v = k + 2): each line's stretches inside both.
struct Lines {
  int k = 0, n = 0;
  double du = 0.0, dv = 0.0;
  std::vector<std::vector<std::pair<double, double>>> stretches;  // per line (i, j) at i * n + j
  double volume = 0.0;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
};

// Lines off the cells' centres by an irrational fraction: CAD geometry sits on round numbers, and a line
// through a vertex or along an edge would count one crossing twice.
constexpr double kOffU = 0.5 + 0.0618034, kOffV = 0.5 + 0.0414214;

// A solid's triangles filed by the lines (of an n x n grid across axis k over the box) their shadows reach,
// so that each line is cut with the few triangles over it, not with all of them.
struct Filed {
  Solid solid;
  std::vector<std::vector<std::uint32_t>> byLine;
};

Filed file(const Solid& all, const Eigen::AlignedBox3d& box, int k, int n, double du, double dv) {
  const int u = (k + 1) % 3, v = (k + 2) % 3;
  Filed f{alongAxis(all, box, k), std::vector<std::vector<std::uint32_t>>(static_cast<std::size_t>(n * n))};
  const auto cell = [&](double x, double lo, double d) { return std::clamp(static_cast<int>(std::floor((x - lo) / d - kOffU + 0.5)), 0, n - 1); };
  for (std::size_t t = 0; t < f.solid.boxes.size(); ++t) {
    const Eigen::AlignedBox3d& b = f.solid.boxes[t];
    const int i0 = cell(b.min()[u], box.min()[u], du) - 1, i1 = cell(b.max()[u], box.min()[u], du) + 1;
    const int j0 = cell(b.min()[v], box.min()[v], dv) - 1, j1 = cell(b.max()[v], box.min()[v], dv) + 1;
    for (int i = std::max(i0, 0); i <= std::min(i1, n - 1); ++i)
      for (int j = std::max(j0, 0); j <= std::min(j1, n - 1); ++j) f.byLine[static_cast<std::size_t>(i * n + j)].push_back(static_cast<std::uint32_t>(t));
  }
  return f;
}

// Crossings of the line through `p` along axis `k` with the triangles filed by that line, sorted.
std::vector<double> crossings(const Filed& f, std::size_t line, const Eigen::Vector3d& p, int k) {
  Solid few;
  for (const std::uint32_t t : f.byLine[line]) few.triangles.push_back(f.solid.triangles[t]);
  return crossings(few, p, k);
}

Lines overlapAlong(const Solid& allA, const Solid& allB, const Eigen::AlignedBox3d& box, int k, int n) {
  const int u = (k + 1) % 3, v = (k + 2) % 3;
  Lines o;
  o.k = k;
  o.n = n;
  o.du = box.sizes()[u] / n;
  o.dv = box.sizes()[v] / n;
  const Filed a = file(allA, box, k, n, o.du, o.dv), b = file(allB, box, k, n, o.du, o.dv);
  o.stretches.resize(static_cast<std::size_t>(n * n));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      Eigen::Vector3d p = box.min();
      p[u] += (i + kOffU) * o.du;
      p[v] += (j + kOffV) * o.dv;
      const auto line = static_cast<std::size_t>(i * n + j);
      const std::vector<double> ca = crossings(a, line, p, k), cb = crossings(b, line, p, k);
      for (std::size_t x = 0; x + 1 < ca.size(); x += 2)
        for (std::size_t y = 0; y + 1 < cb.size(); y += 2) {
          const double lo = std::max({ca[x], cb[y], box.min()[k]}), hi = std::min({ca[x + 1], cb[y + 1], box.max()[k]});
          if (hi <= lo) continue;
          o.stretches[static_cast<std::size_t>(i * n + j)].emplace_back(lo, hi);
          o.volume += (hi - lo) * o.du * o.dv;
          Eigen::Vector3d mid = p;
          mid[k] = 0.5 * (lo + hi);
          o.moment += mid * (hi - lo) * o.du * o.dv;
        }
    }
  return o;
}

// The length of the stretch of `lines` through point p (0 when p is in none).
double stretchThrough(const Lines& lines, const Eigen::AlignedBox3d& box, const Eigen::Vector3d& p) {
  const int u = (lines.k + 1) % 3, v = (lines.k + 2) % 3;
  const auto i = static_cast<int>(std::floor((p[u] - box.min()[u]) / lines.du)), j = static_cast<int>(std::floor((p[v] - box.min()[v]) / lines.dv));
  if (i < 0 || j < 0 || i >= lines.n || j >= lines.n) return 0.0;
  for (const auto& [lo, hi] : lines.stretches[static_cast<std::size_t>(i * lines.n + j)])
    if (p[lines.k] >= lo && p[lines.k] <= hi) return hi - lo;
  return 0.0;
}

// A clash measured on the meshes: the volume along the axis that sees most of it (the mean of three would
// mix their errors); the depth as the overlap's thickness, the largest over points inside both of the
// shortest of the three stretches through the point (a dowel 0.3 mm too large in its hole: 0.3 mm, whatever
// its length); the direction, the axis along which that thickness is measured.
void measureClash(Interference& r, const Solid& a, const Solid& b, const Eigen::AlignedBox3d& common) {
  constexpr int kLines = 48;
  std::array<Lines, 3> lines;
  for (int k = 0; k < 3; ++k) lines[static_cast<std::size_t>(k)] = overlapAlong(a, b, common, k, kLines);
  const Lines& most = *std::max_element(lines.begin(), lines.end(), [](const Lines& x, const Lines& y) { return x.volume < y.volume; });
  r.volume = most.volume;
  r.where = most.volume > 0.0 ? Eigen::Vector3d(most.moment / most.volume) : common.center();
  // Thickness at the middles of the stretches along x: every point inside both lies on one.
  r.depth = 0.0;
  const Lines& along = lines[0];
  for (int i = 0; i < kLines; ++i)
    for (int j = 0; j < kLines; ++j)
      for (const auto& [lo, hi] : along.stretches[static_cast<std::size_t>(i * kLines + j)]) {
        Eigen::Vector3d p = common.min();
        p[1] += (i + kOffU) * along.du;
        p[2] += (j + kOffV) * along.dv;
        // A few points along the stretch, not only its middle: a thin band crossed lengthwise.
        for (const double f : {0.25, 0.5, 0.75}) {
          p[0] = lo + f * (hi - lo);
          double thinnest = hi - lo;
          int axis = 0;
          for (int k = 1; k < 3; ++k) {
            const double s = stretchThrough(lines[static_cast<std::size_t>(k)], common, p);
            if (s > 0.0 && s < thinnest) thinnest = s, axis = k;
          }
          if (thinnest > r.depth) {
            r.depth = thinnest;
            r.direction = Eigen::Vector3d::Unit(axis);
          }
        }
      }
}

}  // namespace

struct OverlapCache {
  std::map<PartId, Solid> solids;
};

std::optional<Interference> overlapAtRest(const CollisionWorld& world, const Assembly& assembly, PartId p, PartId q, OverlapCache* cache) {
  if (p > q) std::swap(p, q);
  // The designed fit between the two (a screw may hold both a thread and a head's seat in one part).
  const Constraint* designed = nullptr;
  for (const Constraint& c : assembly.constraints) {
    const PartId partner = c.partner.value_or(assembly.base.value_or(c.part));
    const bool between = (c.part == p && partner == q) || (c.part == q && partner == p);
    if (between && c.type == Constraint::Type::Insert && c.found && c.found->fit != Constraint::Found::Fit::Clearance) designed = &c;
  }
  const ObjectId a = ObjectId::part(p), b = ObjectId::part(q);
  // Wholly on either side of a face one rests on the other with (a cover on the plate): they only touch,
  // and the queries below would walk every node of the plate to say so.
  if (!designed && world.restOnEachOther(a, b)) {
    Interference contact;
    contact.a = p;
    contact.b = q;
    return contact;
  }
  QueryOptions any;
  any.stopAtFirst = true;
  if (!designed && world.query(a, b, any).contacts.empty()) return std::nullopt;
  Interference r;
  r.a = p;
  r.b = q;
  QueryOptions deep;
  deep.dropTouching = true;
  deep.stopAtFirst = true;
  deep.skipDesigned = true;
  if (!world.query(a, b, deep).contacts.empty()) {
    const Eigen::AlignedBox3d common = world.worldBounds(a).intersection(world.worldBounds(b));
    // A part in many clashes (a plate its bolts stand in) is taken into the world once.
    std::map<PartId, Solid> own;
    std::map<PartId, Solid>& solids = cache ? cache->solids : own;
    for (const PartId x : {p, q})
      if (!solids.count(x)) solids.emplace(x, worldSolid(*assembly.parts[x].mesh, world.pose(ObjectId::part(x))));
    measureClash(r, solids.at(p), solids.at(q), common);
    // No deeper than the two tessellations may lie inside their true surfaces (a head in its countersink,
    // facets of two tessellations of one surface) it cannot be told from touching.
    const double tol = world.tolerances().distance;
    double deflections = 0.0;
    for (const PartId x : {p, q})
      if (assembly.parts[x].cad) deflections += assembly.parts[x].cad->deflection;
    if (r.depth > tol + deflections && r.volume > tol * tol * tol) {
      r.kind = Interference::Kind::Clash;
      return r;
    }
  }
  if (!designed) {
    Interference contact;
    contact.a = p;
    contact.b = q;
    return contact;
  }
  const Constraint::Found& f = *designed->found;
  Interference fit;
  fit.a = p;
  fit.b = q;
  fit.kind = f.fit == Constraint::Found::Fit::Threaded ? Interference::Kind::Threaded : Interference::Kind::Press;
  fit.thread = f.thread;
  const double R = std::max(f.partRadius, f.partnerRadius), rb = std::min(f.partRadius, f.partnerRadius);
  fit.volume = std::numbers::pi * (R * R - rb * rb) * f.overlap;
  fit.depth = R - rb;
  const PartId partner = designed->partner.value_or(*assembly.base);
  const Eigen::Isometry3d& at = world.pose(ObjectId::part(partner));
  fit.direction = (at.linear() * designed->baseAxis.direction).normalized();
  // The middle of the band: on the axis, halfway along where the two overlap.
  const Eigen::Vector3d onAxis = at * designed->baseAxis.point;
  const Eigen::AlignedBox3d both = world.worldBounds(a).intersection(world.worldBounds(b));
  fit.where = onAxis + fit.direction * fit.direction.dot(both.center() - onAxis);
  return fit;
}

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
  // Designed fits are known from the exact faces; a press fit of a few micrometres may not show in the
  // tessellations at all.
  for (const Constraint& c : assembly.constraints)
    if (c.type == Constraint::Type::Insert && c.found && c.found->fit != Constraint::Found::Fit::Clearance && assembly.base) {
      const PartId partner = c.partner.value_or(*assembly.base);
      pairs.emplace_back(std::min(c.part, partner), std::max(c.part, partner));
    }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  OverlapCache cache;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const auto [p, q] = pairs[k];
    if (progress && !progress(static_cast<double>(k) / static_cast<double>(pairs.size()), p, q)) throw LoadCancelled();
    if (auto r = overlapAtRest(world, assembly, p, q, &cache)) out.push_back(std::move(*r));
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
