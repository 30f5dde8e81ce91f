// Sliding with Coulomb friction against closed-form solutions (docs/physics.md, "Sliding").
#include <gtest/gtest.h>

#include <cmath>

#include "vaw/dynamics/gravity.hpp"
#include "vaw/dynamics/slide.hpp"
#include "vaw/units.hpp"

using namespace vaw::dyn;

namespace {

using vaw::kStandardGravity;
using vaw::kDeg;

// An axis tilted `tilt` below the horizontal, pointing downhill.
AxisSlideInput tiltedAxis(double tilt) {
  AxisSlideInput in;
  in.u = Eigen::Vector3d(std::cos(tilt), 0.0, -std::sin(tilt));
  in.g = worldGravity();
  return in;
}

// A plane tilted `tilt` about y; e1 points downhill.
PlaneSlideInput slope(double tilt) {
  PlaneSlideInput in;
  in.n = Eigen::Vector3d(std::sin(tilt), 0, std::cos(tilt));
  in.e1 = Eigen::Vector3d(std::cos(tilt), 0, -std::sin(tilt));
  in.e2 = in.n.cross(in.e1);
  in.g = worldGravity();
  return in;
}

}  // namespace

TEST(Slide, FromRestMatchesClosedFormOver2s) {
  const double tilt = 30 * kDeg;
  const Friction f{0.3, 0.2};
  const double a = kStandardGravity * (std::sin(tilt) - f.fd * std::cos(tilt));
  AxisSlideState s;
  const double h = 1.0 / 90.0;
  const auto in = tiltedAxis(tilt);
  for (int i = 1; i <= 180; ++i) {
    stepAxisSlide(s, in, f, h, Method::Exact);
    const double t = i * h;
    // Tolerance: 1e-12 relative (closed form evaluated incrementally, round-off only).
    ASSERT_NEAR(s.s, 0.5 * a * t * t, 1e-12 * 0.5 * a * t * t) << "t = " << t;
    ASSERT_NEAR(s.v, a * t, 1e-12 * a * t);
  }
}

TEST(Slide, WithInitialVelocityMatchesClosedForm) {
  const double tilt = 25 * kDeg;
  const Friction f{0.3, 0.2};
  const double a = kStandardGravity * (std::sin(tilt) - f.fd * std::cos(tilt));
  AxisSlideState s{0.0, 0.8, true};
  const double h = 1.0 / 60.0;
  for (int i = 1; i <= 120; ++i) {
    stepAxisSlide(s, tiltedAxis(tilt), f, h, Method::Exact);
    const double t = i * h, want = 0.8 * t + 0.5 * a * t * t;
    ASSERT_NEAR(s.s, want, 1e-12 * want);
  }
}

TEST(Slide, StopsAtTheExactTimeInsideTheStep) {
  // Horizontal axis, v0 = 1 m/s: stops at t* = v0 / (fd g), s* = v0^2 / (2 fd g).
  const Friction f{0.3, 0.2};
  AxisSlideState s{0.0, 1.0, true};
  const double tStar = 1.0 / (f.fd * kStandardGravity), sStar = 1.0 / (2.0 * f.fd * kStandardGravity);
  const double h = 1.0 / 90.0;
  double t = 0.0, stopTime = -1.0;
  for (int i = 0; i < 90; ++i) {
    const SlideStep r = stepAxisSlide(s, tiltedAxis(0.0), f, h, Method::Exact);
    if (r.event == SlideEvent::Stopped) stopTime = t + r.eventTime;
    t += h;
  }
  EXPECT_NEAR(stopTime, tStar, 1e-12);
  EXPECT_NEAR(s.s, sStar, 1e-12 * sStar);
  EXPECT_FALSE(s.moving);
  EXPECT_EQ(s.v, 0.0) << "a stopped part has no velocity left to chatter with";
}

TEST(Slide, ThrownUphillStopsThenSlidesBack) {
  const double tilt = 30 * kDeg;  // steeper than the static angle of fs = 0.3 (16.7 deg)
  const Friction f{0.3, 0.2};
  AxisSlideState s{0.0, -1.0, true};  // uphill
  const double up = kStandardGravity * (std::sin(tilt) + f.fd * std::cos(tilt)), down = kStandardGravity * (std::sin(tilt) - f.fd * std::cos(tilt));
  const double tStop = 1.0 / up, sTop = -0.5 / up;
  const double h = 1.0 / 30.0;
  for (int i = 0; i < 30; ++i) stepAxisSlide(s, tiltedAxis(tilt), f, h, Method::Exact);
  // Only an exact stop at tStop followed by an immediate restart lands here.
  EXPECT_TRUE(s.moving);
  const double t = 1.0 - tStop;
  EXPECT_NEAR(s.s, sTop + 0.5 * down * t * t, 1e-12);
}

TEST(Slide, BelowTheStaticAngleNeverMovesNotByARoundOff) {
  const Friction f{0.3, 0.2};
  const double tilt = std::atan(f.fs) - 0.1 * kDeg;
  AxisSlideState s;
  for (int i = 0; i < 900; ++i) {  // 10 s at 90 Hz
    const auto r = stepAxisSlide(s, tiltedAxis(tilt), f, 1.0 / 90.0, Method::Exact);
    ASSERT_EQ(r.event, SlideEvent::None);
  }
  EXPECT_EQ(s.s, 0.0);  // exactly: no creep
  EXPECT_EQ(s.v, 0.0);
  EXPECT_FALSE(s.moving);
}

TEST(Slide, JustAboveTheStaticAngleSlides) {
  const Friction f{0.3, 0.2};
  // The paper's condition: beta < 90 deg - atan(fs), beta between G and the axis; 16.70 deg of tilt for fs = 0.3.
  EXPECT_NEAR(90.0 - staticFrictionAngle(f.fs) / kDeg, 16.6992, 1e-4);
  AxisSlideState s;
  const auto r = stepAxisSlide(s, tiltedAxis(std::atan(f.fs) + 0.1 * kDeg), f, 1.0 / 90.0, Method::Exact);
  EXPECT_EQ(r.event, SlideEvent::Started);
  EXPECT_GT(s.s, 0.0);
}

TEST(Slide, BoundIsLocatedInsideTheStep) {
  const double tilt = 40 * kDeg;
  const Friction f{0.3, 0.2};
  const double a = kStandardGravity * (std::sin(tilt) - f.fd * std::cos(tilt));
  auto in = tiltedAxis(tilt);
  in.upper = 0.05;  // the shoulder 50 mm down the shaft
  AxisSlideState s;
  double t = 0.0, hit = -1.0;
  const double h = 1.0 / 30.0;
  for (int i = 0; i < 30 && hit < 0; ++i) {
    const auto r = stepAxisSlide(s, in, f, h, Method::Exact);
    if (r.event == SlideEvent::ReachedUpper) hit = t + r.eventTime;
    t += h;
  }
  EXPECT_NEAR(hit, std::sqrt(2.0 * 0.05 / a), 1e-12);
  EXPECT_EQ(s.s, 0.05);
  EXPECT_NEAR(s.v, a * hit, 1e-12);
}

TEST(Slide, EveryMethodLocatesTheSameStop) {
  for (Method m : kAllMethods) {
    AxisSlideState s{0.0, 1.0, true};
    double t = 0.0, stopTime = -1.0;
    for (int i = 0; i < 60; ++i) {
      const auto r = stepAxisSlide(s, tiltedAxis(0.0), {0.3, 0.2}, 1.0 / 60.0, m);
      if (r.event == SlideEvent::Stopped) stopTime = t + r.eventTime;
      t += 1.0 / 60.0;
    }
    EXPECT_NEAR(stopTime, 1.0 / (0.2 * kStandardGravity), 1e-12) << name(m);
  }
}

TEST(Slide, DegenerateGeometryIsDefined) {
  const Eigen::Vector3d g = worldGravity();
  EXPECT_FALSE(axisDirection(Eigen::Vector3d::Ones(), Eigen::Vector3d::Ones(), g).has_value()) << "zero-length axis";
  EXPECT_FALSE(lineOfPlanes(Eigen::Vector3d::UnitZ(), -Eigen::Vector3d::UnitZ(), g).has_value()) << "parallel planes";
  const auto line = lineOfPlanes(Eigen::Vector3d(0, 1, 1).normalized(), Eigen::Vector3d(1, 0, 1).normalized(), g);
  ASSERT_TRUE(line);
  EXPECT_GE(line->dot(g), 0.0) << "flipped to point downhill";
  // Gravity along a vertical axis: no normal force, no friction, free fall along the axis.
  AxisSlideInput vertical;
  vertical.u = -Eigen::Vector3d::UnitZ();
  vertical.g = g;
  AxisSlideState s;
  stepAxisSlide(s, vertical, {0.3, 0.2}, 0.1, Method::Exact);
  EXPECT_NEAR(s.s, 0.5 * kStandardGravity * 0.01, 1e-15);
  // Gravity normal to the axis: never starts.
  AxisSlideState h0;
  stepAxisSlide(h0, tiltedAxis(0.0), {0.0, 0.0}, 1.0, Method::Exact);
  EXPECT_FALSE(h0.moving);
  EXPECT_EQ(h0.s, 0.0);
  // Gravity normal to a plane: G_t = 0, nothing moves, nothing is NaN.
  PlaneSlideState p;
  PlaneSlideInput flat;
  flat.g = g;
  stepPlaneSlide(p, flat, {0.0, 0.0}, 1.0, Method::RK4);
  EXPECT_TRUE(p.p.allFinite());
  EXPECT_EQ(p.p.norm(), 0.0);
  // Gravity pulling the part off the surface (base upside down): lost contact.
  PlaneSlideInput upsideDown = flat;
  upsideDown.n = -Eigen::Vector3d::UnitZ();
  upsideDown.e2 = -Eigen::Vector3d::UnitY();
  EXPECT_EQ(stepPlaneSlide(p, upsideDown, {0.3, 0.2}, 0.01, Method::RK4).event, SlideEvent::LostContact);
}

TEST(PlaneSlide, FromRestIsTheOneDimensionalSlide) {
  const double tilt = 30 * kDeg;
  const PlaneSlideInput in = slope(tilt);
  const Friction f{0.3, 0.2};
  PlaneSlideState s;
  for (int i = 0; i < 90; ++i) stepPlaneSlide(s, in, f, 1.0 / 90.0, Method::Exact);
  const double a = kStandardGravity * (std::sin(tilt) - f.fd * std::cos(tilt));
  EXPECT_NEAR(s.p.x(), 0.5 * a, 1e-12);
  EXPECT_NEAR(s.p.y(), 0.0, 1e-15);
}

TEST(PlaneSlide, FrictionOpposesTheVelocityNotTheSlope) {
  // Released with a sideways velocity on a slope: the path curves downhill. The paper's form
  // (friction along the slope) would keep the sideways speed forever.
  const double tilt = 30 * kDeg;
  const PlaneSlideInput in = slope(tilt);
  const Friction f{0.6, 0.5};
  PlaneSlideState fine{Eigen::Vector2d::Zero(), Eigen::Vector2d(0.0, 1.0), true};
  PlaneSlideState coarse = fine;
  for (int i = 0; i < 10000; ++i) stepPlaneSlide(fine, in, f, 1e-4, Method::RK4);
  for (int i = 0; i < 90; ++i) stepPlaneSlide(coarse, in, f, 1.0 / 90.0, Method::RK4);
  // Sideways speed decays (friction component along e2).
  EXPECT_LT(std::abs(fine.v.y()), 0.5);
  EXPECT_GT(fine.p.x(), 0.0);
  // RK4 at 90 Hz against RK4 at 10 kHz: 1 mm after 1 s (stated tolerance for the chart's middle range).
  EXPECT_LT((coarse.p - fine.p).norm(), 1e-3);
}
