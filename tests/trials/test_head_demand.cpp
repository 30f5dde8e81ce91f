// The head-tracking demand against values computed by hand from theta(t) = atan(G t^2 / (2 d)).
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "vaw/human/head_demand.hpp"

using namespace vaw::human;

namespace {
constexpr double kDeg = 180.0 / M_PI;
}

TEST(HeadDemand, PeakRateAtOneMetreIs145DegreesPerSecondAt034Seconds) {
  // By hand: a = 9.81 / 2 = 4.905; t* = (3 a^2)^(-1/4) = 0.34308 s; theta' = 2 a t / (1 + a^2 t^4)
  // = 3.3656 / (4/3) = 2.5242 rad/s = 144.628 deg/s.
  const HeadDemand d = headDemand(9.81, {1.0, 1.0});
  EXPECT_NEAR(d.peakRateTime_s, 0.34308, 1e-5);
  EXPECT_NEAR(d.peakRate_deg_s, 144.628, 1e-3);
  // Fall of 1 m lasts sqrt(2 / 9.81) = 0.45152 s and ends at atan(1) = 45 degrees.
  EXPECT_NEAR(d.fallTime_s, 0.45152, 1e-5);
  EXPECT_NEAR(d.finalAngle_deg, 45.0, 1e-12);
  // Onset acceleration g / d = 9.81 rad/s^2 = 562.07 deg/s^2 (the paper's eq. 12).
  EXPECT_NEAR(d.peakAcceleration_deg_s2, 562.0716, 1e-4);
  EXPECT_EQ(d.peakAccelerationTime_s, 0.0);
}

TEST(HeadDemand, ClosedFormPeakMatchesADenseSearch) {
  // Peak rate (3^(3/4) / 2) sqrt(g / (2 d)); checked against the largest sampled rate for several
  // geometries, so a wrong closed form cannot hide behind one hand-picked case.
  for (double dist : {0.3, 0.6, 1.0, 2.5}) {
    for (double g : {1.0, 2.45, 9.81}) {
      const HeadDemand d = headDemand(g, {dist, 100.0});  // a fall long enough to pass the peak
      EXPECT_NEAR(d.peakRate_deg_s, kDeg * std::pow(3.0, 0.75) / 2.0 * std::sqrt(g / (2.0 * dist)), 1e-9);
      double best = 0.0, bestT = 0.0;
      for (int i = 0; i <= 200000; ++i) {
        const double t = 5.0 * i / 200000.0;
        if (const double r = viewRate(t, g, dist); r > best) { best = r; bestT = t; }
      }
      EXPECT_NEAR(d.peakRate_deg_s, kDeg * best, 1e-5) << "d " << dist << " g " << g;
      EXPECT_NEAR(d.peakRateTime_s, bestT, 5e-5);
    }
  }
}

TEST(HeadDemand, ShortFallPeaksAtLanding) {
  // h = 0.2 m at d = 1 m lands at sqrt(0.4 / 9.81) = 0.20193 s, before the interior peak; the rate there
  // is sqrt(2 h g) / d / (1 + (h/d)^2) = 1.90472 rad/s = 109.132 deg/s.
  const HeadDemand d = headDemand(9.81, {1.0, 0.2});
  EXPECT_NEAR(d.peakRateTime_s, 0.201928, 1e-6);
  EXPECT_NEAR(d.peakRate_deg_s, 109.1324, 1e-4);
}

TEST(HeadDemand, DerivativesAreThoseOfTheAngle) {
  const double g = 9.81, dist = 0.7, h = 1e-5;
  for (double t : {0.05, 0.2, 0.34, 0.6, 1.1}) {
    EXPECT_NEAR(viewRate(t, g, dist), (viewAngle(t + h, g, dist) - viewAngle(t - h, g, dist)) / (2 * h), 1e-7);
    EXPECT_NEAR(viewAcceleration(t, g, dist), (viewRate(t + h, g, dist) - viewRate(t - h, g, dist)) / (2 * h), 1e-6);
  }
  // theta'' is largest in magnitude at release; its most negative value is -(9/16) g / d.
  double minAcc = 0.0;
  for (int i = 0; i <= 100000; ++i) minAcc = std::min(minAcc, viewAcceleration(3.0 * i / 100000.0, g, dist));
  EXPECT_NEAR(minAcc, -9.0 / 16.0 * g / dist, 1e-6);
  EXPECT_NEAR(viewAcceleration(0.0, g, dist), g / dist, 1e-12);
}

TEST(HeadDemand, RatesScaleWithSqrtOfGravityAndAccelerationsLinearly) {
  const ViewingGeometry geo{0.8, 0.5};
  const HeadDemand full = headDemand(9.81, geo), quarter = headDemand(0.25 * 9.81, geo);
  EXPECT_NEAR(quarter.peakRate_deg_s, 0.5 * full.peakRate_deg_s, 1e-9);
  EXPECT_NEAR(quarter.peakAcceleration_deg_s2, 0.25 * full.peakAcceleration_deg_s2, 1e-9);
  EXPECT_NEAR(quarter.fallTime_s, 2.0 * full.fallTime_s, 1e-12);
  EXPECT_EQ(quarter.finalAngle_deg, full.finalAngle_deg);
}

TEST(HeadDemand, RecommendedScaleKeepsTheDemandWithinTheLimit) {
  // Pitch limit 300 deg/s: (300 / 144.628)^2 = 4.3027 -- real gravity is within reach at 1 m.
  const ScaleRecommendation def = recommendScale({1.0, 1.0}, HeadLimits{}, FollowAxis::Pitch, 9.81);
  EXPECT_NEAR(def.maxScale, 4.30265, 1e-5);
  EXPECT_EQ(def.recommendedScale, 1.0);
  EXPECT_EQ(def.limitedBy, "pitch rate");
  // A slower head (a heavy helmet, 100 deg/s): (100 / 144.628)^2 = 0.478073, and the demand at that
  // scale sits exactly on the limit.
  HeadLimits helmet;
  helmet.pitchRate_deg_s = 100.0;
  const ScaleRecommendation slow = recommendScale({1.0, 1.0}, helmet, FollowAxis::Pitch, 9.81);
  EXPECT_NEAR(slow.recommendedScale, 0.478073, 1e-6);
  EXPECT_NEAR(headDemand(9.81 * slow.recommendedScale, {1.0, 1.0}).peakRate_deg_s, 100.0, 1e-9);
  // Yaw uses its own limit: (600 / 144.628)^2 = 17.21.
  EXPECT_NEAR(recommendScale({1.0, 1.0}, HeadLimits{}, FollowAxis::Yaw, 9.81).maxScale, 17.2106, 1e-4);
  // An acceleration limit of 140 deg/s^2 binds first: 140 / 562.07 = 0.24908.
  HeadLimits acc;
  acc.acceleration_deg_s2 = 140.0;
  const ScaleRecommendation byAcc = recommendScale({1.0, 1.0}, acc, FollowAxis::Pitch, 9.81);
  EXPECT_NEAR(byAcc.recommendedScale, 0.249079, 1e-6);
  EXPECT_EQ(byAcc.limitedBy, "acceleration");
}

TEST(HeadDemand, RejectsNonPositiveGeometry) {
  EXPECT_THROW((void)headDemand(9.81, {0.0, 1.0}), std::invalid_argument);
  EXPECT_THROW((void)headDemand(9.81, {1.0, -1.0}), std::invalid_argument);
  EXPECT_THROW((void)headDemand(0.0, {1.0, 1.0}), std::invalid_argument);
  HeadLimits zero;
  zero.pitchRate_deg_s = 0.0;
  EXPECT_THROW((void)recommendScale({1.0, 1.0}, zero), std::invalid_argument);
}
