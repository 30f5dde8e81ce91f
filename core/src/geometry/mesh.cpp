#include "vaw/mesh.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <climits>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <tuple>
#include <unordered_map>
#include <utility>

namespace vaw {

Eigen::AlignedBox3d TriMesh::bounds() const {
  Eigen::AlignedBox3d b;
  for (const auto& v : vertices) b.extend(v);
  return b;
}

void TriMesh::append(const TriMesh& other, const Eigen::Isometry3d& t) {
  const int offset = static_cast<int>(vertices.size());
  if (t.matrix() == Eigen::Matrix4d::Identity()) {
    vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
  } else {
    vertices.reserve(vertices.size() + other.vertices.size());
    for (const auto& v : other.vertices) vertices.push_back(t * v);
  }
  triangles.reserve(triangles.size() + other.triangles.size());
  for (const auto& tri : other.triangles) triangles.push_back(tri.array() + offset);
}

void TriMesh::scale(double factor) {
  for (auto& v : vertices) v *= factor;
}

void TriMesh::transform(const Eigen::Isometry3d& t) {
  for (auto& v : vertices) v = t * v;
}

namespace {

using Cell = std::array<std::int64_t, 3>;

std::uint64_t mix(std::uint64_t h) {  // splitmix64's finalizer
  h ^= h >> 30;
  h *= 0xbf58476d1ce4e5b9ULL;
  h ^= h >> 27;
  h *= 0x94d049bb133111ebULL;
  return h ^ (h >> 31);
}

// An open-addressing hash grid of welded vertices: each occupied slot is one cell, with the chain of
// its vertices in insertion order. Sized to the vertices kept, not to the input: a 15-million-corner
// STL soup welds to a few million.
class WeldGrid {
 public:
  explicit WeldGrid(std::size_t expected) { resize(std::max<std::size_t>(64, std::bit_ceil(expected * 2))); }

  // The first vertex of cell c, or -1.
  [[nodiscard]] std::int32_t first(const Cell& c) const {
    const std::size_t slot = find(c);
    return head_[slot];
  }
  [[nodiscard]] std::int32_t next(std::int32_t v) const { return next_[static_cast<std::size_t>(v)]; }

  void add(std::int32_t v, const Cell& c) {
    cells_.push_back(c);
    next_.push_back(-1);
    std::size_t slot = find(c);
    if (head_[slot] < 0) {
      if (++used_ * 2 > head_.size()) {
        resize(head_.size() * 2);
        slot = find(c);
      }
      head_[slot] = tail_[slot] = v;
    } else {
      next_[static_cast<std::size_t>(tail_[slot])] = v;
      tail_[slot] = v;
    }
  }

 private:
  [[nodiscard]] std::size_t find(const Cell& c) const {
    const std::size_t mask = head_.size() - 1;
    std::size_t slot = mix(static_cast<std::uint64_t>(c[0]) * 73856093u ^ static_cast<std::uint64_t>(c[1]) * 19349663u ^
                           static_cast<std::uint64_t>(c[2]) * 83492791u) &
                       mask;
    while (head_[slot] >= 0 && cells_[static_cast<std::size_t>(head_[slot])] != c) slot = (slot + 1) & mask;
    return slot;
  }
  void resize(std::size_t capacity) {
    const std::vector<std::int32_t> oldHead = std::move(head_), oldTail = std::move(tail_);
    head_.assign(capacity, -1);
    tail_.assign(capacity, -1);
    for (std::size_t i = 0; i < oldHead.size(); ++i)
      if (oldHead[i] >= 0) {
        const std::size_t slot = find(cells_[static_cast<std::size_t>(oldHead[i])]);
        head_[slot] = oldHead[i];
        tail_[slot] = oldTail[i];
      }
  }

  std::vector<std::int32_t> head_, tail_;  // per slot
  std::vector<std::int32_t> next_;         // per vertex
  std::vector<Cell> cells_;                // per vertex
  std::size_t used_ = 0;
};

// Sorts 64-bit keys by their value: four passes of 16 bits, linear in the count (the edge check of a
// 5-million-triangle mesh sorts 15 million keys).
void radixSort(std::vector<std::uint64_t>& keys) {
  std::vector<std::uint64_t> buffer(keys.size());
  std::vector<std::size_t> count(65536);
  for (int shift = 0; shift < 64; shift += 16) {
    std::fill(count.begin(), count.end(), 0);
    for (const std::uint64_t k : keys) ++count[(k >> shift) & 0xffff];
    std::size_t sum = 0;
    for (auto& c : count) sum += std::exchange(c, sum);
    for (const std::uint64_t k : keys) buffer[count[(k >> shift) & 0xffff]++] = k;
    keys.swap(buffer);
  }
}

}  // namespace

std::size_t weldVertices(TriMesh& mesh, double tolerance) {
  if (mesh.vertices.empty()) return 0;
  // Cells 64 tolerances wide: a vertex's neighbours within the tolerance are in its own cell except
  // along the axes where it lies within the tolerance of a cell face, so usually one cell is searched.
  const double cell = tolerance > 0.0 ? 64.0 * tolerance : 1.0;
  const double tol2 = tolerance * tolerance;
  WeldGrid grid(mesh.vertices.size() / 4);
  std::vector<int> remap(mesh.vertices.size());
  std::vector<Eigen::Vector3d> kept;
  kept.reserve(mesh.vertices.size() / 4);
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Eigen::Vector3d& v = mesh.vertices[i];
    if (!v.allFinite()) {  // leave for checkMesh to report; never merge NaNs
      remap[i] = static_cast<int>(kept.size());
      kept.push_back(v);
      grid.add(static_cast<std::int32_t>(kept.size() - 1), Cell{INT64_MIN, INT64_MIN, INT64_MIN});
      continue;
    }
    // Clamped so that a vertex far out (or a tiny tolerance) cannot overflow the integer cell or its
    // neighbours' (undefined behaviour); clamped vertices share edge cells and are still compared by
    // their true distance.
    constexpr double kCellLimit = 4.0e18;  // below 2^63 - 1 with room for the +-1 neighbours
    Cell c{};
    std::array<int, 3> lo{}, hi{};
    for (int a = 0; a < 3; ++a) {
      const double x = v[a] / cell, f = std::floor(x);
      c[static_cast<std::size_t>(a)] = static_cast<std::int64_t>(std::clamp(f, -kCellLimit, kCellLimit));
      lo[static_cast<std::size_t>(a)] = (x - f) * cell <= tolerance ? -1 : 0;
      hi[static_cast<std::size_t>(a)] = (f + 1.0 - x) * cell <= tolerance ? 1 : 0;
    }
    int found = -1;
    for (int dx = lo[0]; dx <= hi[0] && found < 0; ++dx)
      for (int dy = lo[1]; dy <= hi[1] && found < 0; ++dy)
        for (int dz = lo[2]; dz <= hi[2] && found < 0; ++dz)
          for (std::int32_t k = grid.first({c[0] + dx, c[1] + dy, c[2] + dz}); k >= 0 && found < 0; k = grid.next(k))
            if ((kept[static_cast<std::size_t>(k)] - v).squaredNorm() <= tol2) found = k;
    if (found < 0) {
      found = static_cast<int>(kept.size());
      kept.push_back(v);
      grid.add(found, c);
    }
    remap[i] = found;
  }
  const std::size_t removed = mesh.vertices.size() - kept.size();
  mesh.vertices = std::move(kept);
  for (auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k)
      if (t[k] >= 0 && static_cast<std::size_t>(t[k]) < remap.size()) t[k] = remap[static_cast<std::size_t>(t[k])];
  return removed;
}

namespace {
bool degenerate(const TriMesh& m, const Eigen::Vector3i& t, double areaTolerance) {
  if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) return true;
  const auto& a = m.vertices[static_cast<std::size_t>(t[0])];
  const auto& b = m.vertices[static_cast<std::size_t>(t[1])];
  const auto& c = m.vertices[static_cast<std::size_t>(t[2])];
  return 0.5 * (b - a).cross(c - a).norm() <= areaTolerance;
}
bool indicesValid(const TriMesh& m, const Eigen::Vector3i& t) {
  const auto n = static_cast<int>(m.vertices.size());
  return t.minCoeff() >= 0 && t.maxCoeff() < n;
}
}  // namespace

namespace {
std::uint64_t directedEdge(int a, int b) {
  return static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32 | static_cast<std::uint32_t>(b);
}
}  // namespace

MeshRepair repairMesh(TriMesh& mesh, double weldTolerance, double areaTolerance) {
  MeshRepair r;
  r.welded = weldVertices(mesh, weldTolerance);
  const auto before = mesh.triangles.size();
  std::erase_if(mesh.triangles, [&](const Eigen::Vector3i& t) {
    return indicesValid(mesh, t) && (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]);
  });
  r.removed = before - mesh.triangles.size();
  // A split neighbour can itself be a sliver (a fan of them along one edge): a few passes take them all.
  for (int pass = 0; pass < 8; ++pass) {
    std::unordered_map<std::uint64_t, std::size_t> owner;  // directed edge -> its triangle
    owner.reserve(mesh.triangles.size() * 3);
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
      if (indicesValid(mesh, mesh.triangles[i]))
        for (int k = 0; k < 3; ++k) owner[directedEdge(mesh.triangles[i][k], mesh.triangles[i][(k + 1) % 3])] = i;
    std::vector<char> gone(mesh.triangles.size(), 0);
    bool changed = false;
    const std::size_t count = mesh.triangles.size();
    for (std::size_t i = 0; i < count; ++i) {
      const Eigen::Vector3i t = mesh.triangles[i];
      if (gone[i] || !indicesValid(mesh, t) || !degenerate(mesh, t, areaTolerance)) continue;
      int k = 0;  // the longest edge t[k] -> t[k+1]; the third corner lies on it
      double longest = -1.0;
      for (int e = 0; e < 3; ++e) {
        const double l = (mesh.vertices[static_cast<std::size_t>(t[(e + 1) % 3])] - mesh.vertices[static_cast<std::size_t>(t[e])]).squaredNorm();
        if (l > longest) longest = l, k = e;
      }
      const int a = t[k], b = t[(k + 1) % 3], c = t[(k + 2) % 3];
      const auto across = owner.find(directedEdge(b, a));
      gone[i] = 1;
      changed = true;
      if (across == owner.end() || across->second == i || gone[across->second]) {
        ++r.removed;
        continue;
      }
      // The neighbour (b, a, d) becomes (b, c, d) and (c, a, d): the quad b-c-a-d without the sliver.
      const std::size_t j = across->second;
      const Eigen::Vector3i& n = mesh.triangles[j];
      int d = n[0];
      for (int e = 0; e < 3; ++e)
        if (n[e] != a && n[e] != b) d = n[e];
      mesh.triangles[j] = Eigen::Vector3i(b, c, d);
      mesh.triangles.emplace_back(c, a, d);
      gone.push_back(0);
      const std::size_t added = mesh.triangles.size() - 1;
      owner.erase(directedEdge(a, b));
      owner.erase(directedEdge(b, a));
      for (const auto& [from, to, tri] : {std::tuple{b, c, j}, std::tuple{c, d, j}, std::tuple{d, b, j}, std::tuple{c, a, added},
                                          std::tuple{a, d, added}, std::tuple{d, c, added}})
        owner[directedEdge(from, to)] = tri;
      ++r.mended;
    }
    std::size_t at = 0;
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
      if (!gone[i]) mesh.triangles[at++] = mesh.triangles[i];
    mesh.triangles.resize(at);
    if (!changed) break;
  }
  r.check = checkMesh(mesh, areaTolerance);
  return r;
}

MeshCheck checkMesh(const TriMesh& mesh, double areaTolerance) {
  MeshCheck r;
  for (const auto& v : mesh.vertices)
    if (!v.allFinite()) ++r.nonFiniteVertices;

  // Exact duplicates: sort indices by position and count equal neighbours.
  std::vector<std::size_t> order(mesh.vertices.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  auto less = [&](std::size_t a, std::size_t b) {
    const auto& p = mesh.vertices[a];
    const auto& q = mesh.vertices[b];
    return std::lexicographical_compare(p.data(), p.data() + 3, q.data(), q.data() + 3);
  };
  std::sort(order.begin(), order.end(), less);
  for (std::size_t i = 1; i < order.size(); ++i)
    if (mesh.vertices[order[i]] == mesh.vertices[order[i - 1]]) ++r.duplicateVertices;

  // Every edge once, keyed by its two vertices (smaller first) and its direction in the lowest bit, sorted:
  // runs of one undirected edge are then adjacent, with its directions inside the run.
  std::vector<std::uint64_t> edges;
  edges.reserve(mesh.triangles.size() * 3);
  for (const auto& t : mesh.triangles) {
    if (!indicesValid(mesh, t)) { ++r.badIndices; continue; }
    if (degenerate(mesh, t, areaTolerance)) ++r.degenerateTriangles;
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      if (a == b) continue;
      const auto lo = static_cast<std::uint64_t>(std::min(a, b)), hi = static_cast<std::uint64_t>(std::max(a, b));
      edges.push_back(lo << 33 | hi << 1 | (a > b ? 1u : 0u));
    }
  }
  radixSort(edges);
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t end = i, forward = 0;
    while (end < edges.size() && edges[end] >> 1 == edges[i] >> 1) forward += (edges[end++] & 1u) == 0 ? 1 : 0;
    const std::size_t count = end - i, backward = count - forward;
    if (count == 1) ++r.boundaryEdges;
    else if (count > 2) ++r.nonManifoldEdges;
    r.inconsistentEdges += (forward > 1 ? 1 : 0) + (backward > 1 ? 1 : 0);
    i = end;
  }
  return r;
}

std::string MeshCheck::summary() const {
  std::ostringstream s;
  const char* sep = "";
  auto item = [&](std::size_t n, const char* what) {
    if (n == 0) return;
    s << sep << n << ' ' << what;
    sep = ", ";
  };
  item(nonFiniteVertices, "non-finite vertices");
  item(badIndices, "triangles with out-of-range indices");
  item(boundaryEdges, "open (boundary) edges");
  item(nonManifoldEdges, "non-manifold edges");
  item(inconsistentEdges, "edges with inconsistent orientation");
  item(degenerateTriangles, "degenerate triangles");
  item(duplicateVertices, "duplicated vertices");
  const std::string out = s.str();
  return out.empty() ? "closed, consistently oriented" : out;
}

}  // namespace vaw
