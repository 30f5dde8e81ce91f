#include "vaw/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <unordered_map>

namespace vaw {

Eigen::AlignedBox3d TriMesh::bounds() const {
  Eigen::AlignedBox3d b;
  for (const auto& v : vertices) b.extend(v);
  return b;
}

void TriMesh::append(const TriMesh& other, const Eigen::Isometry3d& t) {
  const int offset = static_cast<int>(vertices.size());
  vertices.reserve(vertices.size() + other.vertices.size());
  for (const auto& v : other.vertices) vertices.push_back(t * v);
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

std::uint64_t edgeKey(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

struct CellHash {
  std::size_t operator()(const Eigen::Vector3<std::int64_t>& c) const noexcept {
    auto h = static_cast<std::size_t>(c.x()) * 73856093u;
    h ^= static_cast<std::size_t>(c.y()) * 19349663u;
    h ^= static_cast<std::size_t>(c.z()) * 83492791u;
    return h;
  }
};

}  // namespace

std::size_t weldVertices(TriMesh& mesh, double tolerance) {
  if (mesh.vertices.empty()) return 0;
  const double cell = tolerance > 0.0 ? tolerance : 1e-300;
  using Cell = Eigen::Vector3<std::int64_t>;
  std::unordered_map<Cell, std::vector<int>, CellHash> grid;
  grid.reserve(mesh.vertices.size());
  std::vector<int> remap(mesh.vertices.size());
  std::vector<Eigen::Vector3d> kept;
  kept.reserve(mesh.vertices.size());
  const double tol2 = tolerance * tolerance;
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Eigen::Vector3d& v = mesh.vertices[i];
    if (!v.allFinite()) {  // leave for checkMesh to report; never merge NaNs
      remap[i] = static_cast<int>(kept.size());
      kept.push_back(v);
      continue;
    }
    // Clamped so that a vertex far out (or a tiny tolerance) cannot overflow the integer cell or its
    // neighbours' (undefined behaviour); clamped vertices share edge cells and are still compared by
    // their true distance.
    constexpr double kCellLimit = 4.0e18;  // below 2^63 - 1 with room for the +-1 neighbours
    const Cell c = (v / cell).array().floor().max(-kCellLimit).min(kCellLimit).cast<std::int64_t>();
    int found = -1;
    for (int dx = -1; dx <= 1 && found < 0; ++dx)
      for (int dy = -1; dy <= 1 && found < 0; ++dy)
        for (int dz = -1; dz <= 1 && found < 0; ++dz) {
          auto it = grid.find(c + Cell(dx, dy, dz));
          if (it == grid.end()) continue;
          for (int k : it->second)
            if ((kept[static_cast<std::size_t>(k)] - v).squaredNorm() <= tol2) { found = k; break; }
        }
    if (found < 0) {
      found = static_cast<int>(kept.size());
      kept.push_back(v);
      grid[c].push_back(found);
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

std::size_t removeDegenerateTriangles(TriMesh& mesh, double areaTolerance) {
  const auto before = mesh.triangles.size();
  std::erase_if(mesh.triangles, [&](const Eigen::Vector3i& t) {
    return indicesValid(mesh, t) && degenerate(mesh, t, areaTolerance);
  });
  return before - mesh.triangles.size();
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

  std::unordered_map<std::uint64_t, int> undirected;
  std::unordered_map<std::uint64_t, int> directed;
  undirected.reserve(mesh.triangles.size() * 3);
  directed.reserve(mesh.triangles.size() * 3);
  for (const auto& t : mesh.triangles) {
    if (!indicesValid(mesh, t)) { ++r.badIndices; continue; }
    if (degenerate(mesh, t, areaTolerance)) ++r.degenerateTriangles;
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      if (a == b) continue;
      ++undirected[edgeKey(std::min(a, b), std::max(a, b))];
      ++directed[edgeKey(a, b)];
    }
  }
  for (const auto& [key, count] : undirected) {
    if (count == 1) ++r.boundaryEdges;
    else if (count > 2) ++r.nonManifoldEdges;
  }
  for (const auto& [key, count] : directed)
    if (count > 1) ++r.inconsistentEdges;
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
