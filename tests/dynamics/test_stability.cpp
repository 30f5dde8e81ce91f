// Where the methods fail, found numerically and asserted against theory (docs/physics.md,
// "Stability limits").
#include <gtest/gtest.h>

#include <cmath>

#include "vaw/dynamics/stability.hpp"

using namespace vaw::dyn;

TEST(Stability, PaperSchemeGainsEnergyAtEveryStepSize) {
  // det of its one-step map is 1 + (wn h)^2 / 2 > 1.
  for (double wh = 1e-4; wh < 4.0; wh *= 1.5) {
    const double rho = spectralRadius(Method::PaperExplicit, 1.0, 0.0, wh);
    EXPECT_GT(rho, 1.0) << "wn*dt = " << wh;
    EXPECT_NEAR(rho * rho, 1.0 + 0.5 * wh * wh, 1e-12 * (1 + wh * wh)) << "while the eigenvalues are complex";
    if (wh > 1.9) break;
  }
  EXPECT_EQ(stabilityLimit(Method::PaperExplicit), 0.0);
}

TEST(Stability, LimitsMatchTheory) {
  EXPECT_NEAR(stabilityLimit(Method::SemiImplicitEuler), 2.0, 1e-6);
  EXPECT_NEAR(stabilityLimit(Method::VelocityVerlet), 2.0, 1e-6);
  EXPECT_NEAR(stabilityLimit(Method::RK4), 2.0 * std::sqrt(2.0), 1e-6);
}

TEST(Stability, SymplecticMethodsAreNeutralInsideTheLimit) {
  for (double wh : {0.01, 0.5, 1.0, 1.9})
    for (Method m : {Method::SemiImplicitEuler, Method::VelocityVerlet})
      EXPECT_NEAR(spectralRadius(m, 1.0, 0.0, wh), 1.0, 1e-12) << name(m) << " " << wh;
  EXPECT_LT(spectralRadius(Method::RK4, 1.0, 0.0, 1.0), 1.0) << "RK4 dissipates slowly";
}

TEST(Stability, CheckReportsThePaperGearAt90And30Hz) {
  const double wn = std::sqrt(0.3 * 9.80665 * 0.02 / 4.95e-4);  // 10.9 rad/s
  const auto paper90 = checkStability(Method::PaperExplicit, wn, 0.0, 1.0 / 90);
  EXPECT_FALSE(paper90.stable);
  EXPECT_NEAR(paper90.growthPerSecond, 1.39, 0.01);  // docs/physics.md: about 39 % per second
  const auto paper30 = checkStability(Method::PaperExplicit, wn, 0.0, 1.0 / 30);
  EXPECT_NEAR(paper30.growthPerSecond, 2.6, 0.1);
  EXPECT_NE(paper30.message.find("UNSTABLE"), std::string::npos);
  // Light viscous friction (f_r = 0.0005 N m s) hides it at 90 Hz and not at 30 Hz.
  const double c = 0.0005 / 4.95e-4;
  EXPECT_TRUE(checkStability(Method::PaperExplicit, wn, c, 1.0 / 90).stable);
  EXPECT_FALSE(checkStability(Method::PaperExplicit, wn, c, 1.0 / 30).stable);
  const auto verlet = checkStability(Method::VelocityVerlet, wn, 0.0, 1.0 / 90);
  EXPECT_TRUE(verlet.stable);
  EXPECT_NEAR(verlet.margin, 2.0 / (wn / 90), 1e-5);
  const auto stiff = checkStability(Method::SemiImplicitEuler, 250.0, 0.0, 1.0 / 90);
  EXPECT_FALSE(stiff.stable) << "wn*dt = 2.8 is past the symplectic limit";
}
