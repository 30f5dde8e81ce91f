#include "vaw/dynamics/free_flight.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>
#include <array>

namespace vaw::dyn {

namespace {
Eigen::Quaterniond expMap(const Eigen::Vector3d& rotationVector) {
  const double angle = rotationVector.norm();
  if (angle < 1e-300) return Eigen::Quaterniond::Identity();
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, rotationVector / angle));
}

}  // namespace

Eigen::Quaterniond constantOmegaOrientation(const Release& r, double t) {
  return (expMap(r.omega * (t - r.t0)) * r.orientation).normalized();
}

namespace {

using Motion = TorqueFree::Motion;

Eigen::Vector3d omegaOf(const Motion& m, const Jacobi& j) {
  return {m.amplitude.x() * j.cn, m.sy * m.amplitude.y() * j.sn, m.sz * m.amplitude.z() * j.dn};
}

// Rate of the angle about the angular momentum: (Omega . l + Omega . p) / (1 + l . p), with p = sz e_z.
double psiRateOf(const Motion& m, double dn) {
  const double pOmega = m.amplitude.z() * dn;
  return (m.rateAlong + pOmega) / (1.0 + m.moments.z() * pOmega / m.momentum);
}

// A(t): the smallest rotation taking the unit angular momentum l (pole frame) onto p: (1 + l . p, l x p).
Eigen::Quaterniond swingOf(const Motion& m, const Jacobi& j) {
  const Eigen::Vector3d l = m.moments.cwiseProduct(omegaOf(m, j)) / m.momentum;
  return Eigen::Quaterniond(1.0 + m.sz * l.z(), m.sz * l.y(), -m.sz * l.x(), 0.0).normalized();
}

// Part frame -> world for the elliptic state j and the angle psi: Q Rot_p(psi) A(t) F^-1, with the
// constant outer product Q (.) F^-1 as one 4 x 4 matrix and Rot_p(psi) A(t) multiplied out (p = sz e_z,
// A has no z part).
Eigen::Quaterniond orientationOf(const Motion& m, const Jacobi& j, double psi) {
  const Eigen::Quaterniond a = swingOf(m, j);
  const double c = std::cos(0.5 * psi), zs = m.sz * std::sin(0.5 * psi);
  const Eigen::Vector4d inner(c * a.w(), c * a.x() - zs * a.y(), c * a.y() + zs * a.x(), zs * a.w());  // (w, x, y, z)
  const Eigen::Vector4d q = m.outer * inner;
  return Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
}

Motion makeMotion(const Release& r, const Eigen::Matrix3d& inertia) {
  Motion m;
  m.orientation0 = r.orientation.normalized();
  m.omegaWorld = r.omega;
  const Eigen::Vector3d wPart = m.orientation0.conjugate() * r.omega;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(inertia);
  Eigen::Matrix3d v = eig.eigenvectors();  // columns: principal axes, moments ascending
  if (v.determinant() < 0.0) v.col(2) = -v.col(2);
  const Eigen::Vector3d I = eig.eigenvalues();
  const Eigen::Vector3d wp = v.transpose() * wPart;
  // The pole is the axis whose rate never changes sign: the largest moment's when |L|^2 > 2 E I2.
  const double beyondMiddle = I.dot(((I.array() - I.y()) * wp.array().square()).matrix());
  Eigen::Matrix3d f;
  Eigen::Vector3d w;
  if (beyondMiddle > 0.0) {
    f = v;
    m.moments = I;
    w = wp;
  } else {  // pole on the smallest moment: (v3, -v2, v1) stays right-handed
    f << v.col(2), -v.col(1), v.col(0);
    m.moments = Eigen::Vector3d(I.z(), I.y(), I.x());
    w = Eigen::Vector3d(wp.z(), -wp.y(), wp.x());
  }
  m.frame = Eigen::Quaterniond(f).normalized();
  const double Ix = m.moments.x(), Iy = m.moments.y(), Iz = m.moments.z();
  const Eigen::Array3d Iw2 = m.moments.array() * w.array().square();
  const double twoE = Iw2.sum();
  m.momentum = m.moments.cwiseProduct(w).norm();
  // 2 E Iz - |L|^2, |L|^2 - 2 E Ix and |L|^2 - 2 E Iy as sums of terms of one sign (no cancellation).
  const double d1 = (Iw2 * (Iz - m.moments.array())).sum();
  const double d2 = (Iw2 * (m.moments.array() - Ix)).sum();
  const double dy = (Iw2 * (m.moments.array() - Iy)).sum();
  // A spin about a principal axis, or any spin of a spherical body: Euler's equations give w' = 0 (to
  // round-off, which would otherwise grow on the unstable intermediate axis into a flip the data does not
  // hold).
  const Eigen::Vector3d wDot = m.moments.cwiseProduct(w).cross(w).cwiseQuotient(m.moments);
  if (!(wDot.norm() > 1e-14 * w.squaredNorm())) return m;
  const double lambda2 = (Iz - Iy) * d2 / (Ix * Iy * Iz);
  m.lambda = std::sqrt(std::max(0.0, lambda2));
  if (!(m.lambda > 0.0) || !std::isfinite(m.lambda) || !(m.momentum > 0.0)) return m;
  m.stationary = false;
  m.amplitude = Eigen::Vector3d(std::sqrt(std::max(0.0, d1 / (Ix * (Iz - Ix)))), std::sqrt(std::max(0.0, d1 / (Iy * (Iz - Iy)))),
                                std::sqrt(std::max(0.0, d2 / (Iz * (Iz - Ix)))));
  const double k2 = std::clamp((Iy - Ix) * d1 / ((Iz - Iy) * d2), 0.0, 1.0);
  const double kc2 = std::clamp((Iz - Ix) * dy / ((Iz - Iy) * d2), 0.0, 1.0);
  // The smaller of the two carries the accuracy; the other follows from it.
  if (kc2 < 0.5) {
    m.kc2 = kc2;
    m.k2 = 1.0 - kc2;
  } else {
    m.k2 = k2;
    m.kc2 = 1.0 - k2;
  }
  m.sz = w.z() >= 0.0 ? 1.0 : -1.0;
  m.sy = (Iz > Iy) == (m.sz > 0.0) ? 1.0 : -1.0;
  double cn = m.amplitude.x() > 0.0 ? w.x() / m.amplitude.x() : 0.0;
  double sn = m.amplitude.y() > 0.0 ? m.sy * w.y() / m.amplitude.y() : 0.0;
  const double norm = std::hypot(sn, cn);
  if (norm > 0.0) {
    sn /= norm;
    cn /= norm;
  } else {
    cn = 1.0;
  }
  m.start = {sn, cn, std::sqrt(cn * cn + m.kc2 * sn * sn)};
  m.rateAlong = twoE / m.momentum;
  // Q from the release orientation: R0 F = Q A(0).
  m.q = (m.orientation0 * m.frame * swingOf(m, m.start).conjugate()).normalized();
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector4d e = Eigen::Vector4d::Unit(i);
    const Eigen::Quaterniond column = m.q * Eigen::Quaterniond(e[0], e[1], e[2], e[3]) * m.frame.conjugate();
    m.outer.col(i) << column.w(), column.x(), column.y(), column.z();
  }
  return m;
}

// 8-point Gauss-Legendre on [-1, 1].
constexpr std::array<double, 4> kGaussX{0.1834346424956498, 0.5255324099163290, 0.7966664774136267, 0.9602898564975363};
constexpr std::array<double, 4> kGaussW{0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};

// The integral of psi's rate over [0, span] s after release, by Gauss-Legendre panels half a unit of
// u = lambda t wide (dn's nearest poles are K' >= pi / 2 off the real axis, so each panel is exact to
// round-off).
double psiIntegral(const Motion& m, double span) {
  const auto panels = static_cast<long>(std::ceil(std::abs(span) * m.lambda / 0.5));
  if (panels == 0) return 0.0;
  const double width = span / static_cast<double>(panels);
  double sum = 0.0;
  for (long p = 0; p < panels; ++p) {
    const double mid = (static_cast<double>(p) + 0.5) * width;
    double panel = 0.0;
    for (std::size_t i = 0; i < kGaussX.size(); ++i)
      for (double sign : {-1.0, 1.0}) {
        const double t = mid + sign * kGaussX[i] * 0.5 * width;
        panel += kGaussW[i] * psiRateOf(m, jacobiAdd(m.start, jacobi(m.lambda * t, m.kc2), m.k2, m.kc2).dn);
      }
    sum += 0.5 * width * panel;
  }
  return sum;
}

}  // namespace

TorqueFree::TorqueFree(const Release& r, const Eigen::Matrix3d& inertiaBody)
    : m_(makeMotion(r, inertiaBody)), t0_(r.t0), t_(r.t0), j_(m_.start), q_(m_.orientation0) {
  L_ = m_.orientation0 * (inertiaBody * (m_.orientation0.conjugate() * r.omega));
  if (!m_.stationary) rate0_ = psiRateOf(m_, j_.dn);
}

void TorqueFree::step(double h) {
  if (!(h > 0.0)) return;
  t_ += h;
  if (m_.stationary) {
    q_ = (expMap(m_.omegaWorld * (t_ - t0_)) * m_.orientation0).normalized();
    return;
  }
  if (h != h_) {
    h_ = h;
    jh_ = jacobi(m_.lambda * h, m_.kc2);
    jhHalf_ = jacobi(0.5 * m_.lambda * h, m_.kc2);
  }
  const Jacobi mid = jacobiAdd(j_, jhHalf_, m_.k2, m_.kc2);
  Jacobi end = jacobiAdd(j_, jh_, m_.k2, m_.kc2);
  // Back onto sn^2 + cn^2 = 1, dn^2 + k^2 sn^2 = 1, so that round-off cannot accumulate over a long flight.
  const double norm = 1.0 / std::sqrt(end.sn * end.sn + end.cn * end.cn);
  end.sn *= norm;
  end.cn *= norm;
  end.dn = std::sqrt(end.cn * end.cn + m_.kc2 * end.sn * end.sn);
  const double rate1 = psiRateOf(m_, end.dn);
  psi_ += h / 6.0 * (rate0_ + 4.0 * psiRateOf(m_, mid.dn) + rate1);
  rate0_ = rate1;
  j_ = end;
  q_ = orientationOf(m_, j_, psi_);
}

Eigen::Vector3d TorqueFree::omegaBody() const {
  if (m_.stationary) return m_.orientation0.conjugate() * m_.omegaWorld;
  return m_.frame * omegaOf(m_, j_);
}

double TorqueFree::kineticEnergy() const {
  if (m_.stationary) return 0.5 * m_.omegaWorld.dot(L_);
  const Eigen::Vector3d w = omegaOf(m_, j_);
  return 0.5 * w.dot(m_.moments.cwiseProduct(w));
}

Eigen::Quaterniond TorqueFree::reference(const Release& r, const Eigen::Matrix3d& inertiaBody, double t) {
  const Motion m = makeMotion(r, inertiaBody);
  if (m.stationary) return constantOmegaOrientation(r, t);
  const double span = t - r.t0;
  // psi's rate depends on dn alone, whose period is 2K: integrate one period and the remainder.
  const double period = 2.0 * ellipticK(m.kc2) / m.lambda;
  double psi = 0.0;
  if (std::isfinite(period) && std::abs(span) > period) {
    const double whole = std::trunc(span / period);
    psi = whole * psiIntegral(m, period) + psiIntegral(m, span - whole * period);
  } else {
    psi = psiIntegral(m, span);
  }
  return orientationOf(m, jacobiAdd(m.start, jacobi(m.lambda * span, m.kc2), m.k2, m.kc2), psi);
}

double angleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return a.angularDistance(b);
}

namespace {

// The constant-omega model's largest error against the closed form at the world's step instants, as
// tan^2 of half the angle; stops at the first sample above stopAbove.
double worstHalfTan2(const Release& r, const Eigen::Matrix3d& inertia, double flightTime, double step, double stopAbove) {
  if (!(flightTime > 0.0) || !std::isfinite(flightTime)) return 0.0;
  if (!(step > 0.0) || !std::isfinite(step)) step = flightTime;
  TorqueFree tf(r, inertia);
  if (tf.stationary()) return 0.0;
  // Samples: every m-th world step, m as small as a budget of 32 samples allows, but at most half a
  // radian of turning apart (Simpson's rule on psi stays within 1e-4 of the error it predicts).
  constexpr double kBudget = 32.0, kTurn = 0.5;
  const double n = std::max(1.0, std::ceil(flightTime / step - 1e-9));
  const double turnPerStep = r.omega.norm() * step;
  double m = std::max(1.0, std::ceil(n / kBudget));
  if (turnPerStep > 0.0) m = std::max(1.0, std::min(m, std::floor(kTurn / turnPerStep)));
  const double stride = m * step;
  const auto whole = static_cast<long>(std::floor(n / m));
  const Eigen::Quaterniond q0 = r.orientation.normalized();
  const Eigen::Quaterniond dq = expMap(r.omega * stride);
  Eigen::Quaterniond qc = q0;
  double worst = 0.0;
  const auto measure = [&](const Eigen::Quaterniond& cheap) {
    const Eigen::Quaterniond rel = cheap.conjugate() * tf.orientation();
    const double w2 = rel.w() * rel.w();
    const double t2 = w2 > 0.0 ? rel.vec().squaredNorm() / w2 : std::numeric_limits<double>::infinity();
    worst = std::max(worst, t2);
    return worst > stopAbove;
  };
  for (long k = 1; k <= whole; ++k) {
    tf.step(stride);
    qc = dq * qc;
    if (measure(qc)) return worst;
  }
  const double rest = n - static_cast<double>(whole) * m;
  if (rest > 0.0) {
    tf.step(rest * step);
    measure(expMap(r.omega * (n * step)) * q0);
  }
  return worst;
}

double halfTan2ToAngle(double t2) { return 2.0 * std::atan(std::sqrt(t2)); }

}  // namespace

double predictedConstantOmegaError(const Release& r, const Eigen::Matrix3d& inertiaBody, double flightTime, double step) {
  return halfTan2ToAngle(worstHalfTan2(r, inertiaBody, flightTime, step, std::numeric_limits<double>::infinity()));
}

RotationChoice chooseRotationModel(const Release& r, const Eigen::Matrix3d& inertiaBody, double flightTime, double step, double tol) {
  const double half = std::tan(0.5 * std::min(tol, 3.0));
  RotationChoice c;
  c.predictedError = halfTan2ToAngle(worstHalfTan2(r, inertiaBody, flightTime, step, half * half));
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
