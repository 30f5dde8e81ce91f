#pragma once
// Free flight (PHYSICS.md section 2): the CM follows S0 + V0 t + G_f t^2 / 2 in closed form from the
// release time; orientation by the paper's constant angular velocity or by torque-free rigid-body
// rotation (Euler's equations with quaternion kinematics).
#include <Eigen/Geometry>
#include <string_view>

namespace vaw::dyn {

enum class RotationModel { ConstantOmega, TorqueFree };
constexpr std::string_view name(RotationModel m) { return m == RotationModel::ConstantOmega ? "constant-omega" : "torque-free"; }

struct Release {
  double t0 = 0.0;                                        // s
  Eigen::Vector3d position = Eigen::Vector3d::Zero();     // CM, world, m
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();     // CM, world, m/s
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // part frame -> world
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();        // world, rad/s
};

// Closed-form translation; exact at any time, independent of any step.
inline Eigen::Vector3d ballisticPosition(const Release& r, const Eigen::Vector3d& gScaled, double t) {
  const double dt = t - r.t0;
  return r.position + r.velocity * dt + 0.5 * gScaled * dt * dt;
}
inline Eigen::Vector3d ballisticVelocity(const Release& r, const Eigen::Vector3d& gScaled, double t) {
  return r.velocity + gScaled * (t - r.t0);
}

// The paper's rotation model: R(t) = exp([w0] (t - t0)) R0.
Eigen::Quaterniond constantOmegaOrientation(const Release& r, double t);

// Torque-free rotation: the world angular momentum L = R I R^T w is constant; w wanders.
class TorqueFree {
 public:
  // inertiaBody: about the CM in part-frame axes (kg m^2).
  TorqueFree(const Release& r, const Eigen::Matrix3d& inertiaBody);
  // Advances by h with one classic RK4 step of the quaternion kinematics q' = q (0, w_body) / 2 and
  // renormalizes.
  void step(double h);
  [[nodiscard]] const Eigen::Quaterniond& orientation() const { return q_; }
  [[nodiscard]] Eigen::Vector3d omegaWorld() const;
  [[nodiscard]] Eigen::Vector3d omegaBody() const { return bodyOmega(q_); }
  [[nodiscard]] const Eigen::Vector3d& angularMomentum() const { return L_; }
  [[nodiscard]] double kineticEnergy() const;
  // Reference solution at time t (adaptive Dormand-Prince, tolerance 1e-12) from the release state.
  [[nodiscard]] static Eigen::Quaterniond reference(const Release& r, const Eigen::Matrix3d& inertiaBody, double t);

 private:
  [[nodiscard]] Eigen::Vector3d bodyOmega(const Eigen::Quaterniond& q) const;
  Eigen::Quaterniond q_;
  Eigen::Vector3d L_;  // world
  Eigen::Matrix3d Iinv_;
  Eigen::Matrix3d I_;
};

double angleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b);

// Orientation error of the constant-omega model against torque-free rotation over a flight of the given
// duration, predicted by integrating the faithful model with a fine step (done once, at release).
double predictedConstantOmegaError(const Release& r, const Eigen::Matrix3d& inertiaBody, double flightTime);

struct RotationChoice {
  RotationModel model = RotationModel::ConstantOmega;
  double predictedError = 0.0;  // rad
};
// The cheap model when its predicted error stays below the tolerance (default 1 degree).
RotationChoice chooseRotationModel(const Release& r, const Eigen::Matrix3d& inertiaBody, double flightTime,
                                   double toleranceRad = 1.0 * 3.14159265358979323846 / 180.0);

// Time until the CM, released at r, falls to height zHit under gScaled (z up); infinite if never.
double timeToHeight(const Release& r, const Eigen::Vector3d& gScaled, double zHit);

}  // namespace vaw::dyn
