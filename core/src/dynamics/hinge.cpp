#include "vaw/dynamics/hinge.hpp"

#include <cassert>
#include <cmath>

namespace vaw::dyn {

std::optional<Hinge> Hinge::make(const Eigen::Vector3d& axisPoint, const Eigen::Vector3d& axisDirection,
                                 const Eigen::Isometry3d& partInBase, double mass, const Eigen::Vector3d& com,
                                 const Eigen::Matrix3d& inertiaCm, double rotationalFriction) {
  const double len = axisDirection.norm();
  if (!(len > 1e-12) || !(mass > 0.0)) return std::nullopt;
  Hinge h;
  h.point_ = axisPoint;
  h.u_ = axisDirection / len;
  h.partInBase0_ = partInBase;
  h.m_ = mass;
  h.fr_ = rotationalFriction;
  const Eigen::Vector3d r = partInBase * com - axisPoint;
  h.a_ = r - h.u_ * h.u_.dot(r);
  h.b_ = h.u_.cross(h.a_);
  h.d_ = h.a_.norm();
  // Parallel-axis theorem with the axis expressed in the part's own frame (paper eq. 8, 10).
  const Eigen::Vector3d uPart = partInBase.linear().transpose() * h.u_;
  h.J_ = uPart.dot(inertiaCm * uPart) + mass * h.d_ * h.d_;
  return h;
}

HingeTorque Hinge::torque(const Eigen::Matrix3d& baseRotation, const Eigen::Vector3d& g) const {
  // tau = m u . (r_perp x g) with r_perp(angle) = a cos(angle) + b sin(angle), all in the base frame.
  const Eigen::Vector3d gb = baseRotation.transpose() * g;
  return {m_ * u_.dot(a_.cross(gb)), m_ * u_.dot(b_.cross(gb))};
}

double Hinge::acceleration(const HingeTorque& t, double angle, double omega) const {
  return (t.A * std::cos(angle) + t.B * std::sin(angle) - fr_ * omega) / J_;
}

double Hinge::naturalFrequency(const HingeTorque& t) const { return std::sqrt(std::hypot(t.A, t.B) / J_); }

double Hinge::energy(const HingeTorque& t, const HingeState& s) const {
  // tau = -dV/dangle for V = B cos(angle) - A sin(angle).
  return 0.5 * J_ * s.omega * s.omega + t.B * std::cos(s.angle) - t.A * std::sin(s.angle);
}

void Hinge::step(HingeState& s, const HingeTorque& t, double h, Method m) const {
  assert(supports(kMethods, m));
  const auto f = [this, &t](double, double angle, double omega) { return acceleration(t, angle, omega); };
  const Phase next = vaw::dyn::step(m, f, 0.0, Phase{s.angle, s.omega}, h, -fr_ / J_);
  s.angle = next.x;
  s.omega = next.v;
}

SlideStep stepCylindrical(CylindricalState& s, const Hinge& hinge, const Eigen::Isometry3d& basePose, const Eigen::Vector3d& g,
                          AxisSlideInput slideInput, const Friction& friction, double h, Method m) {
  hinge.step(s.rotation, hinge.torque(basePose.linear(), g), h, m);
  slideInput.u = basePose.linear() * hinge.axisInBase();
  slideInput.g = g;
  // The slide's acceleration is constant within the step, so its closed form is exact whatever
  // method the rotation uses.
  return stepAxisSlide(s.slide, slideInput, friction, h, Method::Exact);
}

Eigen::Isometry3d Hinge::partInBase(double angle, double slide) const {
  Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
  motion.linear() = Eigen::AngleAxisd(angle, u_).toRotationMatrix();
  motion.translation() = point_ - motion.linear() * point_ + u_ * slide;
  return motion * partInBase0_;
}

}  // namespace vaw::dyn
