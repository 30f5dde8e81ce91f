// Rotation about an axis against analytic pendulum solutions (docs/physics.md, "Rotation about an axis").
#include <gtest/gtest.h>

#include <cmath>

#include "vaw/dynamics/gravity.hpp"
#include "vaw/dynamics/hinge.hpp"
#include "vaw/units.hpp"

using namespace vaw::dyn;

namespace {

using vaw::kStandardGravity;

// The paper-like gear (docs/physics.md, "Stability limits"): solid disk r = 0.05 m, m = 0.3 kg, CM 0.02 m off the axis.
struct Gear {
  double m = 0.3, r = 0.05, d = 0.02, fr = 0.0;
  // Axis along base x through the origin, the disk in the base's y-z plane, released with its CM
  // `start` radians from the bottom (pi/2: arm horizontal at (0, d, 0)).
  Hinge make(double start = M_PI / 2) const {
    const Eigen::Matrix3d I = Eigen::Vector3d(0.5 * m * r * r, 0.25 * m * r * r, 0.25 * m * r * r).asDiagonal();
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = Eigen::AngleAxisd(start, Eigen::Vector3d::UnitX()).toRotationMatrix();
    return *Hinge::make(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), pose, m, Eigen::Vector3d(0, 0, -d), I, fr);
  }
};

struct Trace {
  std::vector<double> t, angle;
};

Trace simulate(const Hinge& h, double seconds, double dt, Method m, const Eigen::Matrix3d& base = Eigen::Matrix3d::Identity()) {
  const HingeTorque tq = h.torque(base, worldGravity());
  HingeState s;
  Trace r;
  const auto n = static_cast<long>(std::llround(seconds / dt));
  for (long i = 0; i <= n; ++i) {
    r.t.push_back(static_cast<double>(i) * dt);
    r.angle.push_back(s.angle);
    h.step(s, tq, dt, m);
  }
  return r;
}

// Times where the angle crosses `level` upwards, linearly interpolated.
std::vector<double> crossings(const Trace& r, double level) {
  std::vector<double> out;
  for (std::size_t i = 1; i < r.t.size(); ++i)
    if (r.angle[i - 1] < level && r.angle[i] >= level)
      out.push_back(r.t[i - 1] + (level - r.angle[i - 1]) / (r.angle[i] - r.angle[i - 1]) * (r.t[i] - r.t[i - 1]));
  return out;
}

double meanPeriod(const std::vector<double>& c) { return (c.back() - c.front()) / static_cast<double>(c.size() - 1); }

}  // namespace

TEST(Hinge, ParallelAxisInertiaOfThePaperGear) {
  const Hinge h = Gear{}.make();
  EXPECT_NEAR(h.inertia(), 0.5 * 0.3 * 0.05 * 0.05 + 0.3 * 0.02 * 0.02, 1e-18);
  EXPECT_NEAR(h.inertia(), 4.95e-4, 1e-18);
  EXPECT_NEAR(h.armLength(), 0.02, 1e-16);
  EXPECT_NEAR(h.naturalFrequency(h.torque(Eigen::Matrix3d::Identity(), worldGravity())), std::sqrt(0.3 * kStandardGravity * 0.02 / 4.95e-4), 1e-12);
}

TEST(Hinge, SmallAnglePeriod) {
  // Released 1 degree from the bottom; period 2 pi sqrt(J / (m g d)), the finite-amplitude correction is
  // 1 + theta0^2 / 16 = 1 + 1.9e-5, inside the 5e-5 relative tolerance.
  const double theta0 = M_PI / 180.0;
  const Hinge h = Gear{}.make(theta0);
  const double T0 = 2 * M_PI * std::sqrt(h.inertia() / (0.3 * kStandardGravity * 0.02));
  // The angle coordinate starts at 0 and swings to -2 theta0; its centre is -theta0.
  const Trace r = simulate(h, 10.0, 1e-3, Method::RK4);
  const auto c = crossings(r, -theta0);
  ASSERT_GE(c.size(), 10u);
  EXPECT_NEAR(meanPeriod(c) / T0, 1.0, 5e-5);
}

TEST(Hinge, LargeAnglePeriodMatchesTheEllipticIntegral) {
  for (double deg : {90.0, 150.0}) {
    const double theta0 = deg * M_PI / 180.0;
    const Hinge h = Gear{}.make(theta0);
    const double w0 = std::sqrt(0.3 * kStandardGravity * 0.02 / h.inertia());
    const double T = 4.0 / w0 * std::comp_ellint_1(std::sin(theta0 / 2));
    const Trace r = simulate(h, 10.0, 2e-4, Method::RK4);
    const auto c = crossings(r, -theta0);
    ASSERT_GE(c.size(), 5u);
    EXPECT_NEAR(meanPeriod(c) / T, 1.0, 1e-6) << deg << " degrees";
  }
}

TEST(Hinge, DampedDecayRate) {
  // Linearized: amplitude ~ exp(-f_r t / (2 J)). Small amplitude (2 degrees) keeps the linearization valid.
  Gear gear;
  gear.fr = 0.0005;
  const double theta0 = 2 * M_PI / 180.0;
  const Hinge h = gear.make(theta0);
  const Trace r = simulate(h, 6.0, 1e-3, Method::RK4);
  // Peaks of |angle - centre|: the swing's extremes.
  std::vector<std::pair<double, double>> peaks;
  for (std::size_t i = 1; i + 1 < r.t.size(); ++i) {
    const double a = r.angle[i] + theta0;
    if (a > r.angle[i - 1] + theta0 && a >= r.angle[i + 1] + theta0 && a > 0) peaks.emplace_back(r.t[i], a);
  }
  ASSERT_GE(peaks.size(), 4u);
  const double rate = std::log(peaks.front().second / peaks.back().second) / (peaks.back().first - peaks.front().first);
  EXPECT_NEAR(rate, gear.fr / (2 * h.inertia()), 0.01 * gear.fr / (2 * h.inertia()));
}

TEST(Hinge, PaperSchemeGainsEnergyAsPredicted) {
  // docs/physics.md: at 90 Hz the amplitude grows about 39 % per second; at 30 Hz about 2.6x.
  const Hinge h = Gear{}.make(5 * M_PI / 180.0);
  const HingeTorque tq = h.torque(Eigen::Matrix3d::Identity(), worldGravity());
  const double wn = h.naturalFrequency(tq);
  for (double rate : {90.0, 30.0}) {
    const double dt = 1.0 / rate;
    HingeState s;
    const double e0 = h.energy(tq, s) - h.energy(tq, {-5 * M_PI / 180.0, 0.0});  // above the bottom
    for (int i = 0; i < static_cast<int>(rate); ++i) h.step(s, tq, dt, Method::PaperExplicit);
    const double e1 = h.energy(tq, s) - h.energy(tq, {-5 * M_PI / 180.0, 0.0});
    const double predicted = std::pow(1 + 0.5 * wn * wn * dt * dt, rate / 2.0);  // sqrt(det) per step
    EXPECT_NEAR(std::sqrt(e1 / e0), predicted, 0.03 * predicted) << rate << " Hz";
  }
}

TEST(Hinge, SymplecticEnergyDriftIsBoundedOver60s) {
  // A symplectic method conserves a modified energy, so the true energy error oscillates without growing:
  // amplitude ~ wn h / 2 for semi-implicit Euler (first order) and ~ (wn h)^2 / 4 for Verlet.
  // At 90 Hz (wn h = 0.121) the bounds are 7 % and 0.5 % of the swing energy, with no growth from the
  // first 10 s to the last 10 s of a minute.
  const Hinge h = Gear{}.make(30 * M_PI / 180.0);
  const HingeTorque tq = h.torque(Eigen::Matrix3d::Identity(), worldGravity());
  const HingeState bottom{-30 * M_PI / 180.0, 0.0};
  const double wh = h.naturalFrequency(tq) / 90.0;
  for (Method m : {Method::SemiImplicitEuler, Method::VelocityVerlet}) {
    const double bound = m == Method::SemiImplicitEuler ? 0.6 * wh : 0.35 * wh * wh;
    HingeState s;
    const double e0 = h.energy(tq, s) - h.energy(tq, bottom);
    double firstMax = 0, lastMax = 0;
    const double dt = 1.0 / 90.0;
    for (int i = 0; i < 60 * 90; ++i) {
      h.step(s, tq, dt, m);
      const double err = std::abs(h.energy(tq, s) - h.energy(tq, bottom) - e0) / e0;
      if (i < 900) firstMax = std::max(firstMax, err);
      if (i >= 60 * 90 - 900) lastMax = std::max(lastMax, err);
    }
    EXPECT_LT(firstMax, bound) << name(m);
    EXPECT_LT(lastMax, bound) << name(m);
    EXPECT_LT(lastMax, 1.5 * firstMax) << name(m) << ": no secular drift";
  }
  // RK4 is not symplectic: it loses energy slowly, never gains it.
  HingeState s;
  const double e0 = h.energy(tq, s);
  for (int i = 0; i < 60 * 90; ++i) h.step(s, tq, 1.0 / 90.0, Method::RK4);
  EXPECT_LT(h.energy(tq, s), e0);
}

TEST(Hinge, TiltedAxisFeelsOnlyTheTorqueAlongIt) {
  // Tilting the shaft by `tilt` scales the gravity torque by cos(tilt); the paper's form (full m g d sin)
  // agrees only for a horizontal axis.
  const Hinge h = Gear{}.make();
  const double tilt = 40 * M_PI / 180.0;
  const Eigen::Matrix3d base = Eigen::AngleAxisd(tilt, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const HingeTorque flat = h.torque(Eigen::Matrix3d::Identity(), worldGravity());
  const HingeTorque tilted = h.torque(base, worldGravity());
  EXPECT_NEAR(std::hypot(tilted.A, tilted.B), std::cos(tilt) * std::hypot(flat.A, flat.B), 1e-15);
  EXPECT_NEAR(std::hypot(flat.A, flat.B), 0.3 * kStandardGravity * 0.02, 1e-15);
}

TEST(Hinge, DegenerateGeometryIsDefined) {
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity() * 1e-4;
  EXPECT_FALSE(Hinge::make(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Isometry3d::Identity(), 0.3,
                           Eigen::Vector3d::Zero(), I, 0.0))
      << "zero-length axis";
  // CM on the axis: no torque, the part stays.
  const Hinge onAxis = *Hinge::make(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), Eigen::Isometry3d::Identity(), 0.3,
                                    Eigen::Vector3d::Zero(), I, 0.0);
  HingeState s;
  for (int i = 0; i < 900; ++i) onAxis.step(s, onAxis.torque(Eigen::Matrix3d::Identity(), worldGravity()), 1.0 / 90, Method::RK4);
  EXPECT_EQ(s.angle, 0.0);
  EXPECT_EQ(onAxis.naturalFrequency(onAxis.torque(Eigen::Matrix3d::Identity(), worldGravity())), 0.0);
  // Gravity along the axis (vertical shaft): no torque either.
  const Hinge vertical = *Hinge::make(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), Eigen::Isometry3d::Identity(), 0.3,
                                      Eigen::Vector3d(0.02, 0, 0), I, 0.0);
  const HingeTorque t = vertical.torque(Eigen::Matrix3d::Identity(), worldGravity());
  EXPECT_EQ(t.A, 0.0);
  EXPECT_EQ(t.B, 0.0);
}

TEST(Hinge, StatesTheMethodsItSupports) {
  // Exact has no closed form for a rotation (the torque depends on the angle): it is not in the list,
  // and the settings parsers refuse it there, before anything steps.
  for (Method m : kAllMethods) EXPECT_EQ(supports(Hinge::kMethods, m), m != Method::Exact) << name(m);
  EXPECT_EQ(describe(Hinge::kMethods), "paper-explicit, semi-implicit-euler, velocity-verlet or rk4");
  EXPECT_EQ(parseMethod("rk4", Hinge::kMethods), Method::RK4);
  EXPECT_FALSE(parseMethod("exact", Hinge::kMethods));
  EXPECT_EQ(parseMethod("exact", kSlideMethods), Method::Exact);
}

TEST(Hinge, PartPoseRotatesAboutTheAxisAndSlidesAlongIt) {
  const Hinge h = Gear{}.make();
  const Eigen::Isometry3d p = h.partInBase(M_PI / 2, 0.1);
  // The CM (0, 0, -d) in the part frame; released horizontal: at (0, d, 0) in the base. A quarter turn
  // about +x takes it to (0, 0, d), plus 0.1 m along x.
  EXPECT_LE((p * Eigen::Vector3d(0, 0, -0.02) - Eigen::Vector3d(0.1, 0, 0.02)).norm(), 1e-15);
}
