#include "vaw/swept_volume.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <unordered_map>

#include "vaw/limits.hpp"
#include "../base/on_cores.hpp"

namespace vaw {

namespace {

// A dense grid of bits, rows along x padded to whole words, so that a run along x is a few word operations.
struct Bits {
  Eigen::Vector3i dims = Eigen::Vector3i::Zero();
  std::size_t rowWords = 0;
  std::vector<std::uint64_t> w;

  explicit Bits(const Eigen::Vector3i& d)
      : dims(d), rowWords((static_cast<std::size_t>(d.x()) + 63) / 64),
        w(rowWords * static_cast<std::size_t>(d.y()) * static_cast<std::size_t>(d.z()), 0) {}
  [[nodiscard]] std::size_t row(int y, int z) const { return (static_cast<std::size_t>(z) * dims.y() + y) * rowWords; }
  [[nodiscard]] bool get(int x, int y, int z) const { return (w[row(y, z) + x / 64] >> (x % 64)) & 1U; }
  // Sets x0..x1 (inclusive) of a row; safe while other threads set bits of the same words.
  void setRun(std::size_t r, int x0, int x1) {
    for (int x = x0; x <= x1;) {
      const int bit = x % 64;
      const int n = std::min(64 - bit, x1 - x + 1);
      const std::uint64_t mask = (n == 64 ? ~std::uint64_t{0} : ((std::uint64_t{1} << n) - 1)) << bit;
      // Most marks repeat the last pose's: a read leaves the cache line shared between the threads.
      std::atomic_ref<std::uint64_t> word(w[r + x / 64]);
      if ((word.load(std::memory_order_relaxed) & mask) != mask) word.fetch_or(mask, std::memory_order_relaxed);
      x += n;
    }
  }
};

// Marks every voxel whose box, grown by `grow` voxels on every side, meets the convex hull of a triangle
// at the start and at the end of a move (p[0..2] and p[3..5], in voxel units: voxel i spans [i, i+1]).
// For a move without a turn the hull is the prism the triangle sweeps, and the axes tested are all its
// separating axes (the box's, the triangle's normal, the prism's sides, and the box's axes crossed with
// the triangle's edges and the move), so exactly the voxels that meet it are marked. A turning move
// tests the same axes on all six corners; any axis that separates proves the voxel apart, so a voxel is
// never left out that meets the hull. Columns run along the hull's longest extent; the axes without a
// part along it bound the columns, the others each column's run.
void rasterise(Bits& bits, const Eigen::Vector3d (&p)[6], double grow) {
  const double e = 0.5 + grow;  // half the grown box's edge
  Eigen::Vector3d lo = p[0], hi = p[0];
  for (int i = 1; i < 6; ++i) {
    lo = lo.cwiseMin(p[i]);
    hi = hi.cwiseMax(p[i]);
  }
  int d = 0;
  (hi - lo).maxCoeff(&d);
  const int u = (d + 1) % 3, v = (d + 2) % 3;

  struct Axis { Eigen::Vector3d dir; double lo, hi; };
  Axis axes[20];
  int count = 0;
  const auto add = [&](const Eigen::Vector3d& dir) {
    const double size = dir.cwiseAbs().sum();
    if (!(size > 1e-12)) return;
    Axis& x = axes[count++];
    x.dir = dir / size;  // |dir|_1 = 1: the grown box's half-width along it is e
    x.lo = x.hi = x.dir.dot(p[0]);
    for (int i = 1; i < 6; ++i) {
      const double q = x.dir.dot(p[i]);
      x.lo = std::min(x.lo, q);
      x.hi = std::max(x.hi, q);
    }
  };
  const Eigen::Vector3d edge[3] = {p[1] - p[0], p[2] - p[1], p[0] - p[2]};
  const Eigen::Vector3d move = (p[3] + p[4] + p[5] - p[0] - p[1] - p[2]) / 3.0;
  add(edge[0].cross(edge[1]));
  add((p[4] - p[3]).cross(p[5] - p[4]));
  for (const Eigen::Vector3d& ed : edge) add(ed.cross(move));
  for (int k = 0; k < 3; ++k) {
    for (const Eigen::Vector3d& ed : edge) add(ed.cross(Eigen::Vector3d::Unit(k)));
    add(move.cross(Eigen::Vector3d::Unit(k)));
  }
  // Axes with no part along d bound a row's columns; the rest bound a column's run.
  Axis* const across = axes;
  Axis* const along = std::partition(axes, axes + count, [&](const Axis& x) { return x.dir[d] == 0.0; });

  // The voxels whose centre lies within the grown box of [lower, upper] along an axis.
  const auto first = [&](double lower) { return std::max(0.0, std::ceil(lower - e - 0.5)); };
  const auto last = [&](double upper, int axis) { return std::min(bits.dims[axis] - 1.0, std::floor(upper + e - 0.5)); };
  constexpr double kSlack = 1e-9;  // voxels: rounding goes outwards
  for (int i = static_cast<int>(first(lo[u])); i <= static_cast<int>(last(hi[u], u)); ++i) {
    const double cu = i + 0.5;
    double jLo = first(lo[v]), jHi = last(hi[v], v);
    for (const Axis* x = across; x != along; ++x) {
      const double lower = x->lo - e - x->dir[u] * cu, upper = x->hi + e - x->dir[u] * cu;  // for dir_v * cv
      if (x->dir[v] != 0.0) {
        double c0 = lower / x->dir[v], c1 = upper / x->dir[v];
        if (c0 > c1) std::swap(c0, c1);
        jLo = std::max(jLo, std::ceil(c0 - 0.5 - kSlack));
        jHi = std::min(jHi, std::floor(c1 - 0.5 + kSlack));
      } else if (lower > kSlack || upper < -kSlack) {
        jHi = jLo - 1.0;
      }
    }
    for (int j = static_cast<int>(jLo); j <= static_cast<int>(jHi); ++j) {
      const double cv = j + 0.5;
      double kLo = first(lo[d]), kHi = last(hi[d], d);
      for (const Axis* x = along; x != axes + count && kLo <= kHi; ++x) {
        const double rest = x->dir[u] * cu + x->dir[v] * cv;
        double c0 = (x->lo - e - rest) / x->dir[d], c1 = (x->hi + e - rest) / x->dir[d];
        if (c0 > c1) std::swap(c0, c1);
        kLo = std::max(kLo, std::ceil(c0 - 0.5 - kSlack));
        kHi = std::min(kHi, std::floor(c1 - 0.5 + kSlack));
      }
      if (kLo > kHi) continue;
      Eigen::Vector3i at;
      at[u] = i;
      at[v] = j;
      if (d == 0) {
        bits.setRun(bits.row(at.y(), at.z()), static_cast<int>(kLo), static_cast<int>(kHi));
      } else {
        for (int k = static_cast<int>(kLo); k <= static_cast<int>(kHi); ++k) {
          at[d] = k;
          bits.setRun(bits.row(at.y(), at.z()), at.x(), at.x());
        }
      }
    }
  }
}

// The voxels reachable from the grid's border without passing a marked one (6-neighbours): the outside.
// A scanline fill: runs along x, each run looking for free runs in the four rows beside it.
Bits outside(const Bits& shell) {
  Bits out(shell.dims);
  const int nx = shell.dims.x();
  const auto isFree = [&](std::size_t r, int x) {
    return ((~(shell.w[r + x / 64] | out.w[r + x / 64]) >> (x % 64)) & 1U) != 0;
  };
  struct Run { int y, z, x0, x1; };
  std::vector<Run> stack;
  // Takes the free run through x in row (y, z), marks it and queues it.
  const auto take = [&](int y, int z, int x) {
    const std::size_t r = shell.row(y, z);
    int x0 = x, x1 = x;
    while (x0 > 0 && isFree(r, x0 - 1)) --x0;
    while (x1 + 1 < nx && isFree(r, x1 + 1)) ++x1;
    out.setRun(r, x0, x1);
    stack.push_back({y, z, x0, x1});
    return x1;
  };
  take(0, 0, 0);  // the border layer is never marked (the grid has a free margin), so one seed reaches it all
  while (!stack.empty()) {
    const Run run = stack.back();
    stack.pop_back();
    const int ny[4] = {run.y - 1, run.y + 1, run.y, run.y}, nz[4] = {run.z, run.z, run.z - 1, run.z + 1};
    for (int k = 0; k < 4; ++k) {
      if (ny[k] < 0 || nz[k] < 0 || ny[k] >= shell.dims.y() || nz[k] >= shell.dims.z()) continue;
      const std::size_t r = shell.row(ny[k], nz[k]);
      for (int x = run.x0; x <= run.x1; ++x) {
        // Skip whole words with nothing free.
        if (x % 64 == 0 && (~(shell.w[r + x / 64] | out.w[r + x / 64])) == 0) {
          x += 63;
          continue;
        }
        if (isFree(r, x)) x = take(ny[k], nz[k], x);
      }
    }
  }
  return out;
}

// Which of the 256 ways a 2 x 2 x 2 block of voxels can be filled leave the surface through its middle
// corner a manifold: the filled voxels face-connected within the block, and the empty ones too. (Two
// voxels meeting only along an edge or at a corner would make an edge with four faces or a corner where
// two sheets touch, which CAD systems and the workbench's own reader refuse as a solid.)
const std::array<bool, 256>& manifoldBlocks() {
  static const std::array<bool, 256> table = [] {
    std::array<bool, 256> t{};
    const auto connected = [](unsigned set) {
      if (set == 0) return true;
      unsigned seen = set & (~set + 1), grown = 0;
      while (grown != seen) {
        grown = seen;
        for (unsigned i = 0; i < 8; ++i)
          if (seen >> i & 1U)
            for (unsigned bit : {1U, 2U, 4U}) seen |= (1U << (i ^ bit)) & set;
      }
      return seen == set;
    };
    for (unsigned m = 0; m < 256; ++m) t[m] = connected(m) && connected(~m & 255U);
    return t;
  }();
  return table;
}

// Fills every block whose corner is not a manifold, until none is left: only adds voxels, so the result
// still holds the path; the few added lie next to voxels that were occupied.
void makeManifold(Bits& occ) {
  const auto& ok = manifoldBlocks();
  const Eigen::Vector3i& n = occ.dims;
  for (bool changed = true; changed;) {
    changed = false;
    for (int z = 0; z + 1 < n.z(); ++z)
      for (int y = 0; y + 1 < n.y(); ++y) {
        const std::size_t rows[4] = {occ.row(y, z), occ.row(y + 1, z), occ.row(y, z + 1), occ.row(y + 1, z + 1)};
        for (std::size_t wi = 0; wi < occ.rowWords; ++wi) {
          // Nothing to look at where the four rows agree and are all full or all empty here (and at the
          // next word's first bit, which the last block of this word reaches).
          std::uint64_t any = 0, all = ~std::uint64_t{0};
          for (const std::size_t r : rows) {
            any |= occ.w[r + wi];
            all &= occ.w[r + wi];
          }
          const bool nextAny = wi + 1 < occ.rowWords && std::any_of(std::begin(rows), std::end(rows), [&](std::size_t r) { return occ.w[r + wi + 1] & 1U; });
          const bool nextAll = wi + 1 < occ.rowWords && std::all_of(std::begin(rows), std::end(rows), [&](std::size_t r) { return occ.w[r + wi + 1] & 1U; });
          if (any == 0 && !nextAny) continue;
          if (all == ~std::uint64_t{0} && nextAll) continue;
          const int x0 = static_cast<int>(wi * 64), x1 = std::min(x0 + 63, n.x() - 2);
          for (int x = x0; x <= x1; ++x) {
            unsigned m = 0;
            for (int c = 0; c < 8; ++c)
              if (occ.get(x + (c & 1), y + (c >> 1 & 1), z + (c >> 2 & 1))) m |= 1U << c;
            if (ok[m]) continue;
            for (int c = 0; c < 8; ++c) occ.setRun(occ.row(y + (c >> 1 & 1), z + (c >> 2 & 1)), x + (c & 1), x + (c & 1));
            changed = true;
          }
        }
      }
  }
}

// The faces between occupied voxels and empty ones (or the grid's edge), merged: the exposed faces of each
// plane into rectangles, greedily (from the first face left, as wide as the row allows, then as high as
// whole rows of that width allow). A rectangle is two triangles, or, where another rectangle's corner lies
// on one of its sides, a fan about its centre through every such corner, so that no corner lies inside
// another triangle's edge (no T-junctions). The result is a closed, outward-facing surface, a manifold once
// makeManifold has run, enclosing exactly the voxels' volume, with a fraction of the two triangles a voxel
// face would take (the gearbox gear's 1 mm volume: docs/swept-volume.md).
TriMesh surface(const Bits& occ, const Eigen::Vector3d& origin, double h) {
  const Eigen::Vector3i& dims = occ.dims;
  const auto filled = [&](int x, int y, int z) {
    return x >= 0 && y >= 0 && z >= 0 && x < dims.x() && y < dims.y() && z < dims.z() && occ.get(x, y, z);
  };
  // A face of direction f (+x, -x, +y, -y, +z, -z) lies in the plane `layer` across its axis a = f / 2, at
  // (u, v) along the axes a + 1 and a + 2 (u x v points along +a), so counter-clockwise in (u, v) faces +a.
  struct Face {
    int f, layer, v, u;
    auto operator<=>(const Face&) const = default;
  };
  std::vector<Face> faces;
  static constexpr int kDir[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (int z = 0; z < dims.z(); ++z)
    for (int y = 0; y < dims.y(); ++y) {
      const std::size_t r = occ.row(y, z);
      for (std::size_t wi = 0; wi < occ.rowWords; ++wi) {
        std::uint64_t inside = occ.w[r + wi];
        while (inside) {
          const int x = static_cast<int>(wi * 64) + std::countr_zero(inside);
          inside &= inside - 1;
          const int c[3] = {x, y, z};
          for (int f = 0; f < 6; ++f) {
            if (filled(x + kDir[f][0], y + kDir[f][1], z + kDir[f][2])) continue;
            const int a = f / 2;
            faces.push_back({f, c[a] + (f % 2 == 0 ? 1 : 0), c[(a + 2) % 3], c[(a + 1) % 3]});
          }
        }
      }
    }
  std::sort(faces.begin(), faces.end());

  struct Rect {
    int f, layer, u0, v0, u1, v1;
  };
  std::vector<Rect> rects;
  const auto cell = [](int v, int u) { return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(v)) << 32) | static_cast<std::uint32_t>(u); };
  std::unordered_map<std::uint64_t, bool> left;  // a plane's faces: true while no rectangle has taken it
  for (std::size_t begin = 0, end; begin < faces.size(); begin = end) {
    end = begin;
    left.clear();
    while (end < faces.size() && faces[end].f == faces[begin].f && faces[end].layer == faces[begin].layer) {
      left.emplace(cell(faces[end].v, faces[end].u), true);
      ++end;
    }
    const auto take = [&](int v, int u) {
      const auto it = left.find(cell(v, u));
      return it != left.end() && it->second;
    };
    for (std::size_t i = begin; i < end; ++i) {
      const Face& s = faces[i];
      if (!take(s.v, s.u)) continue;
      int u1 = s.u + 1, v1 = s.v + 1;
      while (take(s.v, u1)) ++u1;
      for (;; ++v1) {
        bool row = true;
        for (int u = s.u; u < u1 && row; ++u) row = take(v1, u);
        if (!row) break;
      }
      for (int v = s.v; v < v1; ++v)
        for (int u = s.u; u < u1; ++u) left[cell(v, u)] = false;
      rects.push_back({s.f, s.layer, s.u, s.v, u1, v1});
    }
  }

  const auto key = [&](const Eigen::Vector3i& p) {
    return static_cast<std::uint64_t>(p.x()) +
           static_cast<std::uint64_t>(dims.x() + 1) * (static_cast<std::uint64_t>(p.y()) + static_cast<std::uint64_t>(dims.y() + 1) * p.z());
  };
  const auto point = [](const Rect& r, int u, int v) {
    Eigen::Vector3i p;
    const int a = r.f / 2;
    p[a] = r.layer;
    p[(a + 1) % 3] = u;
    p[(a + 2) % 3] = v;
    return p;
  };
  std::unordered_map<std::uint64_t, int> corner;  // grid point -> its vertex, for every rectangle's corners
  TriMesh m;
  for (const Rect& r : rects)
    for (const auto& [u, v] : {std::pair{r.u0, r.v0}, {r.u1, r.v0}, {r.u1, r.v1}, {r.u0, r.v1}}) {
      const Eigen::Vector3i p = point(r, u, v);
      if (corner.try_emplace(key(p), static_cast<int>(m.vertices.size())).second) m.vertices.push_back(origin + h * p.cast<double>());
    }
  std::vector<int> ring;
  for (const Rect& r : rects) {
    // The rectangle's border counter-clockwise in (u, v), through every corner that lies on it.
    ring.clear();
    const auto walk = [&](int u, int v, int du, int dv, int steps) {
      for (int s = 0; s < steps; ++s, u += du, v += dv)
        if (const auto it = corner.find(key(point(r, u, v))); it != corner.end()) ring.push_back(it->second);
    };
    walk(r.u0, r.v0, 1, 0, r.u1 - r.u0);
    walk(r.u1, r.v0, 0, 1, r.v1 - r.v0);
    walk(r.u1, r.v1, -1, 0, r.u1 - r.u0);
    walk(r.u0, r.v1, 0, -1, r.v1 - r.v0);
    const bool outward = r.f % 2 == 0;
    const auto add = [&](int a, int b, int c) { outward ? m.triangles.emplace_back(a, b, c) : m.triangles.emplace_back(a, c, b); };
    if (ring.size() == 4) {
      add(ring[0], ring[1], ring[2]);
      add(ring[0], ring[2], ring[3]);
      continue;
    }
    const int centre = static_cast<int>(m.vertices.size());
    const Eigen::Vector3d mid = 0.5 * (point(r, r.u0, r.v0) + point(r, r.u1, r.v1)).cast<double>();
    m.vertices.push_back(origin + h * mid);
    for (std::size_t i = 0; i < ring.size(); ++i) add(centre, ring[i], ring[(i + 1) % ring.size()]);
  }
  return m;
}

}  // namespace

bool SweptVolume::contains(const Eigen::Vector3d& p) const {
  if (occupied.empty() || !(voxel > 0.0)) return false;
  const Eigen::Vector3d g = ((frame.inverse() * p) - origin) / voxel;
  const Eigen::Vector3d f = g.array().floor();
  if ((f.array() < 0).any() || (f.array() >= dims.cast<double>().array()).any()) return false;
  const std::size_t rowWords = (static_cast<std::size_t>(dims.x()) + 63) / 64;
  const int x = static_cast<int>(f.x()), y = static_cast<int>(f.y()), z = static_cast<int>(f.z());
  return (occupied[(static_cast<std::size_t>(z) * dims.y() + y) * rowWords + x / 64] >> (x % 64)) & 1U;
}

TriMesh SweptVolume::surface() const {
  if (occupied.empty()) return {};
  Bits occ(dims);
  if (occ.w.size() != occupied.size()) throw std::logic_error("a swept volume's grid does not match its dimensions");
  occ.w = occupied;
  TriMesh m = vaw::surface(occ, origin, voxel);
  m.transform(frame);
  return m;
}

std::uint64_t sweepVoxelsInMemory(double memoryMB) {
  const double bytes = (memoryMB > 0.0 ? memoryMB : limits::defaultMemoryMB()) * 1048576.0;
  const double voxels = bytes * 8.0 / 3.0;
  return voxels >= static_cast<double>(kMaxSweepVoxels) ? kMaxSweepVoxels : static_cast<std::uint64_t>(std::max(voxels, 0.0));
}

SweptVolume sweep(const TriMesh& mesh, const std::vector<std::vector<Eigen::Isometry3d>>& runs, double voxel, std::uint64_t maxVoxels,
                  double margin) {
  maxVoxels = std::min(maxVoxels, kMaxSweepVoxels);
  if (!(voxel > 0.0) || !std::isfinite(voxel)) throw std::invalid_argument("the voxel must be a positive length, not " + std::to_string(voxel));
  if (!(margin >= 0.0) || !std::isfinite(margin)) throw std::invalid_argument("the margin must be a length of 0 or more, not " + std::to_string(margin));
  if (mesh.vertices.empty() || mesh.triangles.empty()) throw std::invalid_argument("the mesh to sweep has no triangles");
  const Eigen::AlignedBox3d local = mesh.bounds();
  const Eigen::Vector3d centre = local.center();
  double radius = 0.0;
  for (const Eigen::Vector3d& v : mesh.vertices) radius = std::max(radius, (v - centre).norm());

  // The moves. A run's poses are joined into legs, each as long as the poses between its ends lie within an
  // eighth of a voxel of the straight way between them (a point's deviation: the centre's distance from the
  // chord plus the radius times the angle off the interpolated turn), at most 32 steps: a curved carry is
  // thinned, its straight stretches swept whole. A leg that turns is split so that a point's arc leaves its
  // chord by at most another eighth (a point at radius r turning by a strays r (1 - cos(a/2))). Every
  // triangle's hull over a move, grown by the two, holds the triangle wherever it is on that stretch. A run
  // of one pose is a move that stays. The grid holds every pose's box and, for a move that turns, its
  // centre's way grown by the radius, and a free voxel all round (the outside's seed), aligned to whole
  // voxels. Both are counted before anything is allocated.
  const double straying = 0.125 * voxel;
  const double maxTurn = radius > straying ? 2.0 * std::acos(1.0 - straying / radius) : std::numbers::pi;
  struct Leg { std::size_t run, from, to; double off; };  // off: the poses' deviation from it, m
  struct Move { Eigen::Isometry3d from, to; double stray; };  // stray in voxels
  const auto offWay = [&](const std::vector<Eigen::Isometry3d>& run, std::size_t from, std::size_t to) {
    const Eigen::Vector3d c0 = run[from] * centre, chord = run[to] * centre - c0;
    const Eigen::Quaterniond q0(run[from].linear()), q1(run[to].linear());
    double worst = 0.0;
    for (std::size_t k = from + 1; k < to; ++k) {
      const Eigen::Vector3d c = run[k] * centre;
      const double t = chord.squaredNorm() > 0.0 ? std::clamp((c - c0).dot(chord) / chord.squaredNorm(), 0.0, 1.0)
                                                 : static_cast<double>(k - from) / static_cast<double>(to - from);
      worst = std::max(worst, (c - c0 - t * chord).norm() + radius * Eigen::Quaterniond(run[k].linear()).angularDistance(q0.slerp(t, q1)));
    }
    return worst;
  };
  std::vector<Leg> legs;
  Eigen::AlignedBox3d box;
  double moveCount = 0.0;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const auto& run = runs[r];
    for (std::size_t i = 0; i < run.size(); ++i) {
      if (!run[i].matrix().allFinite()) throw std::invalid_argument("pose " + std::to_string(i) + " of the path is not finite");
      for (int k = 0; k < 8; ++k) box.extend(run[i] * local.corner(static_cast<Eigen::AlignedBox3d::CornerType>(k)));
    }
    if (run.size() == 1) legs.push_back({r, 0, 0, 0.0});
    for (std::size_t i = 0; i + 1 < run.size();) {
      std::size_t j = i + 1;
      double off = 0.0;
      while (j + 1 < run.size() && j + 1 - i <= 32) {
        const double wider = offWay(run, i, j + 1);
        if (wider > straying) break;
        off = wider;
        ++j;
      }
      legs.push_back({r, i, j, off});
      i = j;
    }
  }
  for (const Leg& leg : legs) {
    const auto& run = runs[leg.run];
    const double turn = Eigen::Quaterniond(run[leg.from].linear()).angularDistance(Eigen::Quaterniond(run[leg.to].linear()));
    moveCount += std::max(1.0, std::ceil(turn / maxTurn));
    if (turn > 0.0)
      for (const Eigen::Vector3d& c : {run[leg.from] * centre, run[leg.to] * centre})
        box.extend(Eigen::AlignedBox3d(c.array() - radius - leg.off, c.array() + radius + leg.off));
  }
  if (legs.empty()) throw std::invalid_argument("the path has no poses");
  box = Eigen::AlignedBox3d(box.min().array() - margin, box.max().array() + margin);
  const auto gridAt = [&](double v) {
    const Eigen::Vector3d o = ((box.min().array() / v).floor() - 2.0).matrix() * v;
    return std::pair{o, Eigen::Vector3d(((box.max() - o) / v).array().ceil() + 3.0)};
  };
  const auto grid = gridAt(voxel);
  const Eigen::Vector3d origin = grid.first, span = grid.second;
  // The voxel that fits, for the message, rounded up to a tenth of a millimetre as the Path panel sets it:
  // the count goes with the cube of the voxel, the border's voxels aside, so the estimate is grown until
  // the grid fits; the moves go at most with the voxel's inverse.
  const auto larger = [](double m) {
    std::ostringstream o;
    o << "; a larger voxel (" << std::ceil(1e4 * m - 1e-9) / 10.0 << " mm or more) or a shorter span fits";
    return o.str();
  };
  const auto fits = [&](double v) { return gridAt(v).second.prod() <= static_cast<double>(maxVoxels); };
  if (!span.allFinite() || !fits(voxel)) {
    std::string what = "; a larger voxel or a shorter span fits";
    if (span.allFinite()) {
      double v = voxel * std::cbrt(span.prod() / static_cast<double>(std::max<std::uint64_t>(maxVoxels, 1)));
      while (!fits(std::ceil(1e4 * v - 1e-9) / 1e4)) v *= 1.02;
      what = larger(v);
    }
    const std::string why = maxVoxels < kMaxSweepVoxels ? " in the memory a sweep may use" : "";
    throw std::invalid_argument("the path's box needs " + std::to_string(span.prod()) + " voxels of " + std::to_string(1e3 * voxel) +
                                " mm (at most " + std::to_string(maxVoxels) + why + ")" + what);
  }
  if (moveCount > static_cast<double>(kMaxSweepMoves))
    throw std::invalid_argument("the path needs " + std::to_string(moveCount) + " moves at " + std::to_string(1e3 * voxel) +
                                " mm voxels (at most " + std::to_string(kMaxSweepMoves) + ")" +
                                larger(1.05 * voxel * moveCount / static_cast<double>(kMaxSweepMoves)));

  std::vector<Move> moves;
  moves.reserve(static_cast<std::size_t>(moveCount));
  for (const Leg& leg : legs) {
    const Eigen::Isometry3d& a = runs[leg.run][leg.from];
    const Eigen::Isometry3d& b = runs[leg.run][leg.to];
    const Eigen::Quaterniond q0(a.linear()), q1(b.linear());
    const Eigen::Vector3d c0 = a * centre, c1 = b * centre;
    const double turn = q0.angularDistance(q1);
    const int n = std::max(1, static_cast<int>(std::ceil(turn / maxTurn)));
    const auto at = [&](double s) {
      Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
      p.linear() = q0.slerp(s, q1).toRotationMatrix();
      p.translation() = c0 + s * (c1 - c0) - p.linear() * centre;
      return p;
    };
    const double stray = (radius * (1.0 - std::cos(0.5 * turn / n)) + leg.off + margin) / voxel;
    for (int k = 0; k < n; ++k) moves.push_back({k == 0 ? a : at(static_cast<double>(k) / n), k + 1 == n ? b : at(static_cast<double>(k + 1) / n), stray});
  }
  Bits shell(span.cast<int>());

  // Each core takes a stretch of the path (apart, so they seldom write the same words); bits are set
  // with atomic ORs, so no merge is needed. A failure on any (an allocation) ends the sweep with it.
  const std::size_t stretches = std::clamp<std::size_t>(std::thread::hardware_concurrency(), 1, 8);
  vaw::detail::onCores(stretches, [&](std::size_t t, bool) {
    std::vector<Eigen::Vector3d> g0(mesh.vertices.size()), g1(mesh.vertices.size());
    Eigen::Vector3d corners[6];
    for (std::size_t k = t * moves.size() / stretches; k < (t + 1) * moves.size() / stretches; ++k) {
      const Move& m = moves[k];
      for (std::size_t i = 0; i < g0.size(); ++i) {
        g0[i] = (m.from * mesh.vertices[i] - origin) / voxel;
        g1[i] = (m.to * mesh.vertices[i] - origin) / voxel;
      }
      for (const Eigen::Vector3i& tri : mesh.triangles) {
        for (int c = 0; c < 3; ++c) {
          corners[c] = g0[tri[c]];
          corners[c + 3] = g1[tri[c]];
        }
        rasterise(shell, corners, m.stray);
      }
    }
  });
  // Occupied: all that is not outside (the shells and what they enclose), the padding past each row's
  // end left empty.
  Bits occ = outside(shell);
  for (std::uint64_t& w : occ.w) w = ~w;
  if (occ.dims.x() % 64 != 0) {
    const std::uint64_t keep = (std::uint64_t{1} << (occ.dims.x() % 64)) - 1;
    for (std::size_t i = occ.rowWords - 1; i < occ.w.size(); i += occ.rowWords) occ.w[i] &= keep;
  }
  makeManifold(occ);

  SweptVolume sv;
  sv.voxel = voxel;
  sv.moves = moves.size();
  sv.origin = origin;
  sv.dims = occ.dims;
  for (const std::uint64_t w : occ.w) sv.voxels += static_cast<std::size_t>(std::popcount(w));
  sv.volume = static_cast<double>(sv.voxels) * voxel * voxel * voxel;
  sv.mesh = surface(occ, origin, voxel);
  sv.occupied = std::move(occ.w);
  return sv;
}

}  // namespace vaw
