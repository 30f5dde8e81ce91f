#pragma once
// Private to the evaluation module. Products repeat their parts, so the order search's sweeps and the
// ways home's walks both reuse answers by case. A case is fixed by the mover's pose relative to the other
// part, the way in the mover's frame and the length along it, rounded to a nanometre, which is far below
// either search's tolerance.
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdint>

namespace vaw::eval::detail {

using CaseGeometry = std::array<std::int64_t, 16>;

inline CaseGeometry caseGeometry(const Eigen::Isometry3d& mover, const Eigen::Isometry3d& other, const Eigen::Vector3d& out, double length) {
  const Eigen::Isometry3d relative = mover.inverse() * other;
  const Eigen::Vector3d way = mover.linear().transpose() * out;
  const auto q = [](double v) { return static_cast<std::int64_t>(std::llround(v * 1e9)); };
  CaseGeometry g{};
  std::size_t k = 0;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) g[k++] = q(relative.linear()(r, c));
  for (int i = 0; i < 3; ++i) g[k++] = q(relative.translation()[i]);
  for (int i = 0; i < 3; ++i) g[k++] = q(way[i]);
  g[k] = q(length);
  return g;
}

}  // namespace vaw::eval::detail
