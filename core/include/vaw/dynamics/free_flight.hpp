#pragma once
// Free flight (docs/physics.md, "Free flight"): the CM follows S0 + V0 t + G_f t^2 / 2 in closed form from
// the release time; orientation by the paper's constant angular velocity or by torque-free rigid-body
// rotation in closed form.
#include <Eigen/Geometry>
#include <string_view>

#include "vaw/dynamics/elliptic.hpp"

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

// Torque-free rotation in closed form (docs/physics.md, "Free flight"). In the principal frame the body
// rate is a Jacobi elliptic function of time (Landau & Lifshitz, Mechanics, section 37) and the part's
// orientation is R(t) = Q Rot_p(psi(t)) A(t): A(t) is the smallest rotation that turns the unit angular
// momentum (body frame) onto the polhode's pole p, Q a constant rotation, and psi the angle about the
// fixed world angular momentum, whose rate (Omega . (l + p)) / (1 + l . p) depends on dn alone. A step
// advances the elliptic functions exactly by their addition theorem and integrates psi by Simpson's
// rule: the body rate carries no step error, so nothing feeds the instability of a spin near the
// intermediate axis, and the world angular momentum is kept by construction.
class TorqueFree {
 public:
  // inertiaBody: about the CM in part-frame axes (kg m^2), symmetric positive definite.
  TorqueFree(const Release& r, const Eigen::Matrix3d& inertiaBody);
  // Advances by h > 0 (s). A change of h costs two evaluations of the elliptic functions; a constant
  // step costs two additions, a square root and one sine and cosine.
  void step(double h);
  [[nodiscard]] const Eigen::Quaterniond& orientation() const { return q_; }  // part frame -> world
  [[nodiscard]] Eigen::Vector3d omegaWorld() const { return q_ * omegaBody(); }
  [[nodiscard]] Eigen::Vector3d omegaBody() const;  // part frame, rad/s
  [[nodiscard]] const Eigen::Vector3d& angularMomentum() const { return L_; }  // world, constant
  [[nodiscard]] double kineticEnergy() const;  // of the current body rate (J)
  [[nodiscard]] double time() const { return t_; }
  // A spin about a principal axis (or a spherical body): the constant-omega model is exact.
  [[nodiscard]] bool stationary() const { return m_.stationary; }
  // The orientation at time t, evaluated without steps: the elliptic functions from scratch and psi
  // by 8-point Gauss-Legendre panels over at most one period of dn plus whole periods. Accurate to
  // about 1e-13 rad over tens of seconds (tests/dynamics/test_free_flight.cpp checks it against an
  // independent long-double integration of Euler's equations).
  [[nodiscard]] static Eigen::Quaterniond reference(const Release& r, const Eigen::Matrix3d& inertiaBody, double t);

  // The constants of one motion (public for the reference and the model choice; not part of the state).
  struct Motion {
    bool stationary = true;                // a spin about a principal axis (or none): constant omega
    Eigen::Quaterniond frame;              // principal frame (x, y, z; z the pole) -> part frame
    Eigen::Quaterniond q;                  // Q: the pole frame at psi = 0 -> world
    Eigen::Matrix4d outer;                 // the coefficients (w, x, y, z) of Q r F^-1 from those of r
    Eigen::Vector3d moments;               // Ix, Iy, Iz
    Eigen::Vector3d amplitude;             // ax, ay, az: Omega = (ax cn, sy ay sn, sz az dn)
    double sy = 1.0, sz = 1.0;
    double lambda = 0.0;                   // rad/s: u = lambda t
    double k2 = 0.0, kc2 = 1.0;            // parameter and complementary parameter
    double momentum = 0.0;                 // |L|
    double rateAlong = 0.0;                // Omega . l = 2E / |L|
    Jacobi start;                          // sn, cn, dn at release
    Eigen::Vector3d omegaWorld = Eigen::Vector3d::Zero();  // at release (stationary motion)
    Eigen::Quaterniond orientation0;       // at release
  };

 private:
  [[nodiscard]] double psiRate(double dn) const;
  void updateOrientation();

  Motion m_;
  Eigen::Vector3d L_;
  double t0_ = 0.0, t_ = 0.0;
  double psi_ = 0.0;
  Jacobi j_;
  double rate0_ = 0.0;  // psiRate at the current time
  double h_ = 0.0;      // the step the constants below are for
  Jacobi jh_, jhHalf_;
  Eigen::Quaterniond q_;
};

double angleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b);

// Orientation error of the constant-omega model against torque-free rotation over a flight of the given
// duration, at the instants the world will show: its steps of `step` seconds (every m-th one, and the
// last, when the flight has more steps than the prediction's budget of samples).
double predictedConstantOmegaError(const Release& r, const Eigen::Matrix3d& inertiaBody, double flightTime, double step);

struct RotationChoice {
  RotationModel model = RotationModel::ConstantOmega;
  // rad: the constant-omega model's largest error over the flight; once it exceeds the tolerance the
  // prediction stops there, so for a TorqueFree choice it is the error at the first sample above it.
  double predictedError = 0.0;
};
// The cheap model when its predicted error stays below the tolerance (default 1 degree).
RotationChoice chooseRotationModel(const Release& r, const Eigen::Matrix3d& inertiaBody, double flightTime, double step,
                                   double toleranceRad = 1.0 * 3.14159265358979323846 / 180.0);

// Time until the CM, released at r, falls to height zHit under gScaled (z up); infinite if never.
double timeToHeight(const Release& r, const Eigen::Vector3d& gScaled, double zHit);

}  // namespace vaw::dyn
