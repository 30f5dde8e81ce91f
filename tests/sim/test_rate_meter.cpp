// The real rate the status bar shows when the simulation cannot keep up (docs/simulation.md, "When the
// simulation falls behind"), on clocks the test sets.
#include <gtest/gtest.h>

#include "vaw/sim/rate_meter.hpp"

namespace vaw::sim {
namespace {

TEST(RateMeter, MeasuresSimulatedSecondsPerWallSecondOverItsWindow) {
  RateMeter m(2.0);
  EXPECT_FALSE(m.reading()) << "nothing measured yet";
  // 60 ticks a second; the world advances 0.8 s per wall second and stepping takes 30 % of the time.
  for (int k = 0; k <= 60; ++k) m.sample(k / 60.0, 0.8 * k / 60.0, k == 0 ? 0.0 : 0.3 / 60.0);
  ASSERT_TRUE(m.reading()) << "a second measured: half the window";
  EXPECT_NEAR(m.reading()->rate, 0.8, 1e-12);
  EXPECT_NEAR(m.reading()->steppingShare, 0.3, 1e-12);
  // It catches up: after two more seconds at full speed only those count.
  for (int k = 61; k <= 180; ++k) m.sample(k / 60.0, 0.8 + (k - 60) / 60.0, 0.1 / 60.0);
  EXPECT_NEAR(m.reading()->rate, 1.0, 1e-12);
  EXPECT_NEAR(m.reading()->steppingShare, 0.1, 1e-12);
}

TEST(RateMeter, ForgetsThePastOnResetAndWhenTimeGoesBack) {
  RateMeter m(2.0);
  for (int k = 0; k <= 120; ++k) m.sample(k / 60.0, 0.5 * k / 60.0, 0.0);
  m.reset();
  EXPECT_FALSE(m.reading());
  for (int k = 0; k <= 120; ++k) m.sample(10.0 + k / 60.0, 5.0 + k / 60.0, 0.0);
  EXPECT_NEAR(m.reading()->rate, 1.0, 1e-12);
  m.sample(12.1, 0.0, 0.0);  // a seek back: the simulated time fell
  EXPECT_FALSE(m.reading());
}

TEST(RateMeter, BehindBelowNinetyFivePercentAndCaughtUpAboveNinetyEight) {
  EXPECT_FALSE(fallingBehind({0.96, 0.0}, 1.0, false));
  EXPECT_TRUE(fallingBehind({0.94, 0.0}, 1.0, false));
  EXPECT_TRUE(fallingBehind({0.97, 0.0}, 1.0, true)) << "no flicker between 95 and 98 %";
  EXPECT_FALSE(fallingBehind({0.99, 0.0}, 1.0, true));
  EXPECT_TRUE(fallingBehind({0.9, 0.0}, 2.0, false)) << "against the speed asked for";
  EXPECT_FALSE(fallingBehind({0.5, 0.0}, 0.5, false));
}

}  // namespace
}  // namespace vaw::sim
