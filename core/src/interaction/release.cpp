#include "vaw/interaction/release.hpp"

#include <Eigen/Dense>

namespace vaw::interact {

namespace {
// Rotation vector (axis * angle) of a unit quaternion, shortest way round.
Eigen::Vector3d logMap(Eigen::Quaterniond q) {
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  const Eigen::AngleAxisd aa(q);
  return aa.axis() * aa.angle();
}
}  // namespace

Twist twoInstanceVelocity(std::span<const PoseSample> h) {
  Twist out;
  if (h.size() < 2) return out;
  const PoseSample& a = h[h.size() - 2];
  const PoseSample& b = h.back();
  const double dt = b.t - a.t;
  if (!(dt > 0.0)) return out;
  out.linear = (b.position - a.position) / dt;
  out.angular = logMap(b.orientation * a.orientation.conjugate()) / dt;
  return out;
}

Twist windowedVelocity(std::span<const PoseSample> h, double window) {
  if (h.empty()) return {};
  const double tEnd = h.back().t;
  std::size_t first = h.size() - 1;
  while (first > 0 && tEnd - h[first - 1].t <= window + 1e-9) --first;
  const std::size_t n = h.size() - first;
  if (n < 4) return twoInstanceVelocity(h);
  // Fit x(t) = c0 + c1 tau + c2 tau^2 with tau = t - tEnd: the velocity at release is c1.
  Eigen::MatrixXd A(static_cast<Eigen::Index>(n), 3);
  Eigen::MatrixXd Y(static_cast<Eigen::Index>(n), 6);
  const Eigen::Quaterniond qEnd = h.back().orientation;
  for (std::size_t i = 0; i < n; ++i) {
    const PoseSample& s = h[first + i];
    const double tau = s.t - tEnd;
    const auto r = static_cast<Eigen::Index>(i);
    A.row(r) << 1.0, tau, tau * tau;
    Y.block<1, 3>(r, 0) = s.position.transpose();
    Y.block<1, 3>(r, 3) = logMap(s.orientation * qEnd.conjugate()).transpose();
  }
  const Eigen::MatrixXd C = A.colPivHouseholderQr().solve(Y);
  Twist out;
  out.linear = C.block<1, 3>(1, 0).transpose();
  out.angular = C.block<1, 3>(1, 3).transpose();
  return out;
}

Twist releaseVelocity(std::span<const PoseSample> h, const ReleaseSettings& s) {
  return s.estimator == ReleaseEstimator::TwoInstance ? twoInstanceVelocity(h) : windowedVelocity(h, s.window);
}

}  // namespace vaw::interact
