#pragma once
// Rotation about an axis of any direction (docs/physics.md, "Rotation about an axis", with the paper's
// errata): gravity torque projected on the axis, J from the inertia tensor and the parallel-axis theorem,
// viscous friction f_r. The cylindrical case (paper picture 10) adds a slide along the same axis
// (slide.hpp).
#include <Eigen/Geometry>
#include <array>
#include <optional>

#include "vaw/dynamics/integrators.hpp"
#include "vaw/dynamics/slide.hpp"

namespace vaw::dyn {

struct HingeState {
  double angle = 0.0;  // rad about the axis, from the release configuration
  double omega = 0.0;  // rad/s
};

// The gravity torque about the axis as a function of the angle: tau(angle) = A cos(angle) + B sin(angle)
// (N m). A and B depend on the base's orientation and on gravity, so they are recomputed per step.
struct HingeTorque {
  double A = 0.0;
  double B = 0.0;
};

class Hinge {
 public:
  // Every method but Exact: the torque depends on the angle, so the acceleration is not constant
  // within a step and the constant-acceleration closed form does not exist.
  static constexpr std::array kMethods{Method::PaperExplicit, Method::SemiImplicitEuler, Method::VelocityVerlet, Method::RK4};

  // axisPoint, axisDirection: the axis in the base's frame. partInBase: the part frame relative to the
  // base frame at release. com, inertiaCm: in the part frame. A zero-length axis gives nothing.
  static std::optional<Hinge> make(const Eigen::Vector3d& axisPoint, const Eigen::Vector3d& axisDirection,
                                   const Eigen::Isometry3d& partInBase, double mass, const Eigen::Vector3d& com,
                                   const Eigen::Matrix3d& inertiaCm, double rotationalFriction);

  [[nodiscard]] double inertia() const { return J_; }        // kg m^2 about the axis
  [[nodiscard]] double armLength() const { return d_; }      // m, CM to axis
  [[nodiscard]] double mass() const { return m_; }
  [[nodiscard]] double friction() const { return fr_; }      // N m s
  void setFriction(double rotationalFriction) { fr_ = rotationalFriction; }
  [[nodiscard]] const Eigen::Vector3d& axisInBase() const { return u_; }

  // Coefficients of the gravity torque for the base's current orientation (base -> world) and gravity.
  [[nodiscard]] HingeTorque torque(const Eigen::Matrix3d& baseRotation, const Eigen::Vector3d& g) const;
  [[nodiscard]] double acceleration(const HingeTorque& t, double angle, double omega) const;
  // Small-oscillation angular frequency about the stable equilibrium: sqrt(|tau|max / J).
  [[nodiscard]] double naturalFrequency(const HingeTorque& t) const;
  // Kinetic plus gravitational potential energy (J), for drift measurements.
  [[nodiscard]] double energy(const HingeTorque& t, const HingeState& s) const;

  // m must be one of kMethods (checked where the method is chosen: the settings parsers).
  void step(HingeState& s, const HingeTorque& t, double h, Method m) const;

  // The part frame relative to the base after rotating by `angle` and sliding by `slide` along the axis.
  [[nodiscard]] Eigen::Isometry3d partInBase(double angle, double slide = 0.0) const;

 private:
  Eigen::Vector3d point_, u_;      // axis in base frame
  Eigen::Vector3d a_, b_;          // CM arm at release (perpendicular to u) and u x a, base frame
  Eigen::Isometry3d partInBase0_;
  double m_ = 0, J_ = 0, d_ = 0, fr_ = 0;
};

// Rotation and slide on one axis together (paper picture 10): the rotation as above, the slide along
// the same axis with Coulomb friction (slide.hpp, normal force from gravity's part across the axis).
struct CylindricalState {
  HingeState rotation;
  AxisSlideState slide;
};

// One step of both: the rotation with `m`, the slide in closed form. `slideInput` gives the slide's
// bounds (u and g are set from the hinge's axis, the base's orientation and g). Returns the slide's event.
SlideStep stepCylindrical(CylindricalState& s, const Hinge& hinge, const Eigen::Isometry3d& basePose, const Eigen::Vector3d& g,
                          AxisSlideInput slideInput, const Friction& friction, double h, Method m);

}  // namespace vaw::dyn
