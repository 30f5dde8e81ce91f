#include "vaw/primitives.hpp"

#include <cmath>
#include <numbers>

namespace vaw::primitives {

namespace {

struct Builder {
  TriMesh m;
  int vertex(double x, double y, double z) {
    m.vertices.emplace_back(x, y, z);
    return static_cast<int>(m.vertices.size()) - 1;
  }
  // Adds a triangle wound counter-clockwise as seen from `outward`.
  void tri(int a, int b, int c, const Eigen::Vector3d& outward) {
    const auto& pa = m.vertices[static_cast<std::size_t>(a)];
    const Eigen::Vector3d n = (m.vertices[static_cast<std::size_t>(b)] - pa).cross(m.vertices[static_cast<std::size_t>(c)] - pa);
    if (n.dot(outward) >= 0.0) m.triangles.emplace_back(a, b, c);
    else m.triangles.emplace_back(a, c, b);
  }
  void quad(int a, int b, int c, int d, const Eigen::Vector3d& outward) {
    tri(a, b, c, outward);
    tri(a, c, d, outward);
  }
};

Eigen::Vector3d radial(double angle) { return {std::cos(angle), std::sin(angle), 0.0}; }

}  // namespace

TriMesh box(const Eigen::Vector3d& size) {
  Builder b;
  const Eigen::Vector3d h = size / 2.0;
  int v[8];
  for (int i = 0; i < 8; ++i)
    v[i] = b.vertex((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(), (i & 4) ? h.z() : -h.z());
  b.quad(v[0], v[2], v[6], v[4], {-1, 0, 0});
  b.quad(v[1], v[3], v[7], v[5], {1, 0, 0});
  b.quad(v[0], v[1], v[5], v[4], {0, -1, 0});
  b.quad(v[2], v[3], v[7], v[6], {0, 1, 0});
  b.quad(v[0], v[1], v[3], v[2], {0, 0, -1});
  b.quad(v[4], v[5], v[7], v[6], {0, 0, 1});
  return std::move(b.m);
}

TriMesh gridBox(const Eigen::Vector3d& size, int n) {
  TriMesh m;
  const Eigen::Vector3d h = size / 2.0;
  // Each face: axis a fixed at +-h[a], the other two axes b, c gridded.
  for (int a = 0; a < 3; ++a)
    for (double side : {-1.0, 1.0}) {
      const int b = (a + 1) % 3, c = (a + 2) % 3;
      const int first = static_cast<int>(m.vertices.size());
      for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) {
          Eigen::Vector3d v;
          v[a] = side * h[a];
          v[b] = -h[b] + size[b] * i / n;
          v[c] = -h[c] + size[c] * j / n;
          m.vertices.push_back(v);
        }
      auto id = [&](int i, int j) { return first + i * (n + 1) + j; };
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          // (b, c, a) is right-handed, so counter-clockwise in (b, c) faces +a.
          if (side > 0) {
            m.triangles.emplace_back(id(i, j), id(i + 1, j), id(i + 1, j + 1));
            m.triangles.emplace_back(id(i, j), id(i + 1, j + 1), id(i, j + 1));
          } else {
            m.triangles.emplace_back(id(i, j), id(i + 1, j + 1), id(i + 1, j));
            m.triangles.emplace_back(id(i, j), id(i, j + 1), id(i + 1, j + 1));
          }
        }
    }
  weldVertices(m, 1e-12);
  return m;
}

TriMesh cylinder(double radius, double height, int segments) {
  Builder b;
  const double z = height / 2.0;
  const int cb = b.vertex(0, 0, -z), ct = b.vertex(0, 0, z);
  std::vector<int> lo(static_cast<std::size_t>(segments)), hi(static_cast<std::size_t>(segments));
  const double step = 2.0 * std::numbers::pi / segments;
  for (int i = 0; i < segments; ++i) {
    const Eigen::Vector3d r = radius * radial(i * step);
    lo[static_cast<std::size_t>(i)] = b.vertex(r.x(), r.y(), -z);
    hi[static_cast<std::size_t>(i)] = b.vertex(r.x(), r.y(), z);
  }
  for (int i = 0; i < segments; ++i) {
    const auto a = static_cast<std::size_t>(i), n = static_cast<std::size_t>((i + 1) % segments);
    b.tri(cb, lo[a], lo[n], {0, 0, -1});
    b.tri(ct, hi[a], hi[n], {0, 0, 1});
    b.quad(lo[a], lo[n], hi[n], hi[a], radial((i + 0.5) * step));
  }
  return std::move(b.m);
}

TriMesh tube(double outerRadius, double innerRadius, double height, int segments) {
  Builder b;
  const double z = height / 2.0;
  const auto n = static_cast<std::size_t>(segments);
  std::vector<int> ol(n), oh(n), il(n), ih(n);
  const double step = 2.0 * std::numbers::pi / segments;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d d = radial(static_cast<double>(i) * step);
    ol[i] = b.vertex(outerRadius * d.x(), outerRadius * d.y(), -z);
    oh[i] = b.vertex(outerRadius * d.x(), outerRadius * d.y(), z);
    il[i] = b.vertex(innerRadius * d.x(), innerRadius * d.y(), -z);
    ih[i] = b.vertex(innerRadius * d.x(), innerRadius * d.y(), z);
  }
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    const Eigen::Vector3d mid = radial((static_cast<double>(i) + 0.5) * step);
    b.quad(ol[i], ol[j], oh[j], oh[i], mid);
    b.quad(il[i], il[j], ih[j], ih[i], -mid);
    b.quad(il[i], il[j], ol[j], ol[i], {0, 0, -1});
    b.quad(ih[i], ih[j], oh[j], oh[i], {0, 0, 1});
  }
  return std::move(b.m);
}

TriMesh sphere(double radius, int segments, int rings) {
  Builder b;
  const int north = b.vertex(0, 0, radius), south = b.vertex(0, 0, -radius);
  std::vector<std::vector<int>> ring(static_cast<std::size_t>(rings - 1));
  for (int r = 1; r < rings; ++r) {
    const double theta = std::numbers::pi * r / rings;
    for (int s = 0; s < segments; ++s) {
      const double phi = 2.0 * std::numbers::pi * s / segments;
      ring[static_cast<std::size_t>(r - 1)].push_back(
          b.vertex(radius * std::sin(theta) * std::cos(phi), radius * std::sin(theta) * std::sin(phi), radius * std::cos(theta)));
    }
  }
  auto centre = [&](int a, int c, int d) {
    return (b.m.vertices[static_cast<std::size_t>(a)] + b.m.vertices[static_cast<std::size_t>(c)] +
            b.m.vertices[static_cast<std::size_t>(d)]).eval();
  };
  const auto segs = static_cast<std::size_t>(segments);
  for (std::size_t s = 0; s < segs; ++s) {
    const std::size_t t = (s + 1) % segs;
    const auto& first = ring.front();
    const auto& last = ring.back();
    b.tri(north, first[s], first[t], centre(north, first[s], first[t]));
    b.tri(south, last[s], last[t], centre(south, last[s], last[t]));
    for (std::size_t r = 0; r + 1 < ring.size(); ++r) {
      const auto& u = ring[r];
      const auto& w = ring[r + 1];
      b.quad(u[s], u[t], w[t], w[s], centre(u[s], u[t], w[t]));
    }
  }
  return std::move(b.m);
}

}  // namespace vaw::primitives
