// The base moves (held in the left hand): constraint directions follow it every step; the cylindrical
// case; inertial forces from the base's acceleration (an option); gravity scale per motion kind.
#include <gtest/gtest.h>

#include <cmath>

#include "vaw/dynamics/free_flight.hpp"
#include "vaw/dynamics/gravity.hpp"
#include "vaw/dynamics/hinge.hpp"
#include "vaw/dynamics/slide.hpp"
#include "vaw/units.hpp"

using namespace vaw::dyn;

namespace {
using vaw::kDeg;
Eigen::Isometry3d tiltedAboutY(double angle) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitY()).toRotationMatrix();
  return T;
}
}  // namespace

TEST(MovingBase, BlockStartsWhenTheBaseIsTiltedPastTheStaticAngle) {
  // Paper picture 7: the base is tilted slowly (2 degrees per second); the block on its top face
  // stays until the tilt passes atan(fs) = 16.70 degrees, then slides.
  const Friction f{0.3, 0.2};
  PlaneSlideState s;
  const double h = 1.0 / 90.0;
  double startTilt = -1.0;
  for (int i = 1; i <= 90 * 12 && startTilt < 0; ++i) {
    const double tilt = 2.0 * kDeg * i * h;
    const auto r = stepPlaneSlide(s, planeInWorld(Eigen::Vector3d::UnitZ(), tiltedAboutY(tilt), worldGravity()), f, h, Method::Exact);
    if (r.event == SlideEvent::Started) startTilt = tilt;
    else ASSERT_EQ(s.p.norm(), 0.0) << "moved before starting, at " << tilt / kDeg << " degrees";
  }
  // Within one step's tilt (2/90 degree) above the static angle.
  EXPECT_GT(startTilt, std::atan(f.fs));
  EXPECT_LT(startTilt, std::atan(f.fs) + 2.0 * kDeg / 90.0 + 1e-12);
}

TEST(MovingBase, SleeveSlidesTheOtherWayWhenTheShaftIsTurnedOver) {
  // Paper picture 5: the same shaft direction in the base frame, the base turned upside down: the
  // sleeve's motion along the base's +z reverses.
  const Friction f{0.3, 0.2};
  AxisSlideState up, down;
  stepAxisSlide(up, axisInWorld(Eigen::Vector3d::UnitZ(), Eigen::Isometry3d::Identity(), worldGravity()), f, 0.1, Method::Exact);
  stepAxisSlide(down, axisInWorld(Eigen::Vector3d::UnitZ(), tiltedAboutY(M_PI), worldGravity()), f, 0.1, Method::Exact);
  EXPECT_NEAR(up.s, -0.5 * 9.80665 * 0.01, 1e-15) << "falls along -z of an upright base";
  EXPECT_NEAR(down.s, 0.5 * 9.80665 * 0.01, 1e-15) << "and along +z of the base turned over";
}

TEST(MovingBase, InertialForcesAreAnOptionWithAVisibleEffect) {
  // A block on a level plate whose base accelerates at 4 m/s^2 sideways: more than fs g = 2.94 m/s^2,
  // so in the base's frame the block slips backwards when inertial forces are on, and stays when off.
  const Friction f{0.3, 0.2};
  const Eigen::Vector3d baseAcceleration(4.0, 0.0, 0.0);
  for (bool inertial : {false, true}) {
    PlaneSlideState s;
    const Eigen::Vector3d g = effectiveGravity(worldGravity(), baseAcceleration, inertial);
    const PlaneSlideInput in = planeInWorld(Eigen::Vector3d::UnitZ(), Eigen::Isometry3d::Identity(), g);
    for (int i = 0; i < 45; ++i) stepPlaneSlide(s, in, f, 1.0 / 90, Method::Exact);
    const double worldX = s.p.x() * in.e1.x() + s.p.y() * in.e2.x();
    if (inertial) {
      // Relative acceleration -(4 - fd g) along x for 0.5 s, exact in closed form.
      EXPECT_NEAR(worldX, 0.5 * -(4.0 - f.fd * 9.80665) * 0.25, 1e-12);
    } else {
      EXPECT_EQ(s.p.norm(), 0.0);
    }
  }
}

TEST(MovingBase, HingeTorqueFollowsTheBase) {
  // The paper's gear on a shaft whose base is turned about the shaft's own axis: the equilibrium turns
  // with the base, so the torque at the same relative angle changes.
  const Eigen::Matrix3d I = Eigen::Vector3d(3.75e-4, 1.875e-4, 1.875e-4).asDiagonal();
  const Hinge h = *Hinge::make(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), Eigen::Isometry3d::Identity(), 0.3,
                               Eigen::Vector3d(0, 0.02, 0), I, 0.0);
  Eigen::Isometry3d turned = Eigen::Isometry3d::Identity();
  turned.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const HingeTorque t0 = h.torque(Eigen::Matrix3d::Identity(), worldGravity());
  const HingeTorque t1 = h.torque(turned.linear(), worldGravity());
  const double mgd = 0.3 * 9.80665 * 0.02;
  EXPECT_NEAR(h.acceleration(t0, 0.0, 0.0) * h.inertia(), -mgd, 1e-15) << "arm horizontal: full torque";
  EXPECT_NEAR(h.acceleration(t1, 0.0, 0.0) * h.inertia(), 0.0, 1e-15) << "base turned a quarter: arm hangs straight down";
}

TEST(Cylindrical, GearRotatesAndSlidesDownATiltedShaft) {
  // Paper picture 10: the shaft tilted 20 degrees; the gear swings with the gravity torque across the
  // axis (cos 20 of the level one) and slides down with a = g (sin 20 - fd cos 20).
  const Eigen::Matrix3d I = Eigen::Vector3d(3.75e-4, 1.875e-4, 1.875e-4).asDiagonal();
  Eigen::Isometry3d start = Eigen::Isometry3d::Identity();
  start.linear() = Eigen::AngleAxisd(5 * kDeg, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Hinge h = *Hinge::make(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), start, 0.3, Eigen::Vector3d(0, 0, -0.02), I, 0.0);
  const double tilt = 20 * kDeg;
  const Eigen::Isometry3d base = tiltedAboutY(tilt);  // +x now points down the slope
  const Friction f{0.15, 0.1};
  CylindricalState s;
  AxisSlideInput bounds;
  const double dt = 1e-3;
  std::vector<double> ups;
  double prev = 0.0;
  for (int i = 1; i <= 4000; ++i) {
    stepCylindrical(s, h, base, worldGravity(), bounds, f, dt, Method::RK4);
    const double centre = -5 * kDeg;
    if (prev < centre && s.rotation.angle >= centre) ups.push_back(i * dt);
    prev = s.rotation.angle;
  }
  const double a = 9.80665 * (std::sin(tilt) - f.fd * std::cos(tilt));
  EXPECT_NEAR(s.slide.s, 0.5 * a * 16.0, 1e-9) << "slid down the shaft by the closed form";
  ASSERT_GE(ups.size(), 3u);
  const double period = (ups.back() - ups.front()) / static_cast<double>(ups.size() - 1);
  const double level = 2 * M_PI * std::sqrt(h.inertia() / (0.3 * 9.80665 * 0.02));
  // Small-amplitude period scales as 1/sqrt(cos tilt); 5 degree amplitude adds 0.05 %: tolerance 0.2 %.
  EXPECT_NEAR(period / (level / std::sqrt(std::cos(tilt))), 1.0, 2e-3);
}

TEST(GravityScale, DefaultsAndEffect) {
  const GravityScales s;
  EXPECT_EQ(s.freeFlight, 0.25);  // the paper's 0.2-0.3 in a headset
  EXPECT_EQ(s.slide, 1.0);
  EXPECT_EQ(s.rotation, 1.0);
  Release r;
  r.position = {0, 0, 1.0};
  // A quarter of the gravity doubles the time to fall the same height.
  EXPECT_NEAR(timeToHeight(r, s.freeFlight * worldGravity(), 0.0) / timeToHeight(r, worldGravity(), 0.0), 2.0, 1e-12);
}
