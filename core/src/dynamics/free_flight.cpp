#include "vaw/dynamics/free_flight.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "vaw/dynamics/reference.hpp"

namespace vaw::dyn {

namespace {
Eigen::Quaterniond expMap(const Eigen::Vector3d& rotationVector) {
  const double angle = rotationVector.norm();
  if (angle < 1e-300) return Eigen::Quaterniond::Identity();
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, rotationVector / angle));
}

Eigen::Vector4d qdot(const Eigen::Vector4d& q, const Eigen::Vector3d& w) {
  // q = (w, x, y, z) as a 4-vector; derivative of q for body angular velocity w: q (0, w) / 2.
  const double qw = q[0], qx = q[1], qy = q[2], qz = q[3];
  return 0.5 * Eigen::Vector4d(-qx * w.x() - qy * w.y() - qz * w.z(), qw * w.x() + qy * w.z() - qz * w.y(),
                               qw * w.y() + qz * w.x() - qx * w.z(), qw * w.z() + qx * w.y() - qy * w.x());
}

Eigen::Vector4d asVec(const Eigen::Quaterniond& q) { return {q.w(), q.x(), q.y(), q.z()}; }
Eigen::Quaterniond asQuat(const Eigen::Vector4d& v) { return Eigen::Quaterniond(v[0], v[1], v[2], v[3]).normalized(); }
}  // namespace

Eigen::Quaterniond constantOmegaOrientation(const Release& r, double t) {
  return (expMap(r.omega * (t - r.t0)) * r.orientation).normalized();
}

TorqueFree::TorqueFree(const Release& r, const Eigen::Matrix3d& inertiaBody)
    : q_(r.orientation.normalized()), Iinv_(inertiaBody.inverse()), I_(inertiaBody) {
  const Eigen::Matrix3d R = q_.toRotationMatrix();
  L_ = R * I_ * R.transpose() * r.omega;
}

Eigen::Vector3d TorqueFree::bodyOmega(const Eigen::Quaterniond& q) const {
  return Iinv_ * (q.conjugate() * L_);
}

void TorqueFree::step(double h) {
  auto f = [&](const Eigen::Vector4d& q) { return qdot(q, bodyOmega(asQuat(q))); };
  const Eigen::Vector4d y = asVec(q_);
  const Eigen::Vector4d k1 = f(y);
  const Eigen::Vector4d k2 = f(y + 0.5 * h * k1);
  const Eigen::Vector4d k3 = f(y + 0.5 * h * k2);
  const Eigen::Vector4d k4 = f(y + h * k3);
  q_ = asQuat(y + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4));
}

Eigen::Vector3d TorqueFree::omegaWorld() const { return q_ * bodyOmega(q_); }

double TorqueFree::kineticEnergy() const {
  const Eigen::Vector3d w = bodyOmega(q_);
  return 0.5 * w.dot(I_ * w);
}

Eigen::Quaterniond TorqueFree::reference(const Release& r, const Eigen::Matrix3d& inertiaBody, double t) {
  const Eigen::Matrix3d Iinv = inertiaBody.inverse();
  const Eigen::Matrix3d R0 = r.orientation.normalized().toRotationMatrix();
  const Eigen::Vector3d L = R0 * inertiaBody * R0.transpose() * r.omega;
  // The exact flow keeps |q| = 1; the tight tolerance keeps the drift at round-off.
  auto f = [&](double, const Eigen::Vector4d& q) {
    const Eigen::Quaterniond qq = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized();
    const Eigen::Vector3d wb = Iinv * (qq.conjugate() * L);
    return qdot(q, wb);
  };
  return asQuat(integrateReference(f, r.t0, asVec(r.orientation.normalized()), t));
}

double angleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return a.angularDistance(b);
}

double predictedConstantOmegaError(const Release& r, const Eigen::Matrix3d& inertiaBody, double flightTime) {
  if (!(flightTime > 0.0) || !std::isfinite(flightTime)) return 0.0;
  // 64 RK4 steps per flight, at least 200 per revolution: far below the 1 degree tolerance.
  const double w = r.omega.norm();
  const int n = std::clamp(static_cast<int>(std::ceil(std::max(64.0, 200.0 * w * flightTime / (2 * M_PI)))), 64, 20000);
  const double h = flightTime / n;
  TorqueFree tf(r, inertiaBody);
  double worst = 0.0;
  for (int i = 1; i <= n; ++i) {
    tf.step(h);
    worst = std::max(worst, angleBetween(tf.orientation(), constantOmegaOrientation(r, r.t0 + i * h)));
  }
  return worst;
}

RotationChoice chooseRotationModel(const Release& r, const Eigen::Matrix3d& inertiaBody, double flightTime, double tol) {
  RotationChoice c;
  c.predictedError = predictedConstantOmegaError(r, inertiaBody, flightTime);
  c.model = c.predictedError <= tol ? RotationModel::ConstantOmega : RotationModel::TorqueFree;
  return c;
}

double timeToHeight(const Release& r, const Eigen::Vector3d& g, double zHit) {
  // z0 + vz t + gz t^2 / 2 = zHit: the later root is when the falling CM passes zHit.
  const double a = 0.5 * g.z(), b = r.velocity.z(), c = r.position.z() - zHit;
  if (a == 0.0) return b < 0.0 && c > 0.0 ? -c / b : std::numeric_limits<double>::infinity();
  const double disc = b * b - 4 * a * c;
  if (disc < 0.0) return std::numeric_limits<double>::infinity();
  const double s = std::sqrt(disc);
  const double t1 = (-b - s) / (2 * a), t2 = (-b + s) / (2 * a);
  const double t = std::max(t1, t2);
  return t >= 0.0 ? t : std::numeric_limits<double>::infinity();
}

}  // namespace vaw::dyn
