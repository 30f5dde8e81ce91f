// The analysis's numerical helpers against tabulated values.
#include <gtest/gtest.h>

#include <cmath>

#include "trials/numerics.hpp"

using namespace vaw::trials::detail;

TEST(Numerics, QuantilesMatchTables) {
  EXPECT_NEAR(normalQuantile(0.975), 1.959963985, 1e-9);
  EXPECT_NEAR(normalCdf(1.959963985), 0.975, 1e-9);
  EXPECT_NEAR(chiSquare1Quantile(0.95), 3.841458821, 1e-8);
  // Student t, two-sided 95 %: 12.706 (1 dof), 2.262 (9), 2.045 (29).
  EXPECT_NEAR(studentTQuantile(0.975, 1), 12.70620474, 1e-6);
  EXPECT_NEAR(studentTQuantile(0.975, 9), 2.262157163, 1e-8);
  EXPECT_NEAR(studentTQuantile(0.975, 29), 2.045229642, 1e-8);
  EXPECT_NEAR(studentTQuantile(0.025, 9), -2.262157163, 1e-8);
}

TEST(Numerics, BinomialHalfCdfCountsOutcomes) {
  // P(X <= 2) for Bin(10, 1/2) = (1 + 10 + 45) / 1024.
  EXPECT_NEAR(binomialHalfCdf(2, 10), 56.0 / 1024.0, 1e-14);
  EXPECT_EQ(binomialHalfCdf(-1, 10), 0.0);
  EXPECT_EQ(binomialHalfCdf(10, 10), 1.0);
}

TEST(Numerics, GoldenSectionAndBisectionFindKnownPoints) {
  // A smooth minimum is located to about sqrt(machine epsilon): closer, f no longer changes.
  EXPECT_NEAR(goldenMinimize([](double x) { return (x - 0.3) * (x - 0.3) + 2.0; }, -1.0, 2.0, 1e-10), 0.3, 5e-8);
  EXPECT_NEAR(goldenMinimize([](double x) { return std::cosh(x - 1.7); }, 0.0, 5.0, 1e-10), 1.7, 5e-8);
  // A minimum at the bracket's end is found there.
  EXPECT_NEAR(goldenMinimize([](double x) { return x; }, 1.0, 2.0, 1e-10), 1.0, 1e-9);
  EXPECT_NEAR(bisectRoot([](double x) { return x * x - 2.0; }, 0.0, 2.0, 1e-12), std::sqrt(2.0), 1e-11);
  EXPECT_THROW((void)bisectRoot([](double x) { return x * x + 1.0; }, -1.0, 1.0, 1e-6), std::invalid_argument);
}
