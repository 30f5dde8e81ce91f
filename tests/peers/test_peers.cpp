// The Bullet / ODE peers solve the same slide and pendulum as the workbench's reduced models
// (docs/work-precision.md). Every engine compiled in is tested (one instantiation per engine).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "vaw/peers/peers.hpp"

namespace {

using vaw::dyn::kSampleInterval;
using vaw::peers::Peer;
constexpr double kG = 9.80665;

std::vector<std::string> engineNames() {
  std::vector<std::string> names;
  for (const auto& p : vaw::peers::availablePeers()) names.push_back(p.name);
  return names;
}

Peer peerNamed(const std::string& name) {
  for (auto& p : vaw::peers::availablePeers())
    if (p.name == name) return p;
  throw std::runtime_error("no peer " + name);
}

// Fast timing for tests: one timed run.
vaw::dyn::WorkPrecisionOptions quick() {
  vaw::dyn::WorkPrecisionOptions o;
  o.repeats = 1;
  o.minTimedSeconds = 0.0;
  return o;
}

// Times of the sign changes of the samples, linearly interpolated (accurate here because a
// pendulum's angle has an inflection at each zero crossing).
std::vector<double> zeroCrossings(const vaw::dyn::Samples& x) {
  std::vector<double> t;
  for (std::size_t i = 1; i < x.size(); ++i)
    if ((x[i - 1] < 0.0) != (x[i] < 0.0) && x[i - 1] != x[i])
      t.push_back((static_cast<double>(i - 1) + x[i - 1] / (x[i - 1] - x[i])) * kSampleInterval);
  return t;
}

double smallAmplitudePeriod(const vaw::dyn::PendulumScenario& p) {
  return 2.0 * std::numbers::pi * std::sqrt(p.inertia() / (p.mass * kG * p.arm));
}

// Mean period from the first to the last zero crossing (NaN with fewer than two crossings).
double measuredPeriod(const vaw::dyn::Samples& x) {
  const auto z = zeroCrossings(x);
  if (z.size() < 2) return std::nan("");
  return 2.0 * (z.back() - z.front()) / static_cast<double>(z.size() - 1);
}

double stopDistance(const vaw::dyn::SlideScenario& s) {
  const double th = s.tiltDeg * std::numbers::pi / 180.0;
  return s.v0 * s.v0 / (2.0 * kG * (s.fd * std::cos(th) - std::sin(th)));
}

class PeerTest : public ::testing::TestWithParam<std::string> {
 protected:
  Peer peer = peerNamed(GetParam());
};

TEST_P(PeerTest, PendulumSmallAmplitudePeriod) {
  vaw::dyn::PendulumScenario p;
  p.theta0Deg = 5.0;
  p.fr = 0.0;
  const auto r = peer.pendulum(p, 1000, quick());
  ASSERT_EQ(r.samples.size(), vaw::dyn::pendulumReference(p).size());
  EXPECT_NEAR(r.samples[0], p.theta0Deg * std::numbers::pi / 180.0, 1e-12);
  ASSERT_GE(zeroCrossings(r.samples).size(), 20u);  // about 17 periods in 10 s
  const double period = measuredPeriod(r.samples);
  const double expected = smallAmplitudePeriod(p);
  // 1 %: the finite amplitude adds theta0^2/16 = 0.05 %, the 0.1 s sampling with linear
  // interpolation of the crossings about 1e-4; an engine step or inertia mistake shows as more.
  EXPECT_NEAR(period / expected, 1.0, 0.01) << "period " << period << " s, expected " << expected << " s";
  std::printf("[ %s ] pendulum 5 deg at 1000 Hz: period %.6f s, small-amplitude %.6f s (%+.3f %%)\n",
              peer.name.c_str(), period, expected, 100.0 * (period / expected - 1.0));
  EXPECT_GT(r.cpuPerSimSecond, 0.0);
  EXPECT_EQ(r.note.find("WARNING"), std::string::npos) << r.note;
}

// The viscous hinge friction is the peers' own torque -fr * omega (neither engine has it): with
// fr = 0.0005 the amplitude falls to exp(-fr t / 2J) = 0.7 % in 10 s, so a missing or wrong-signed
// torque is off by about theta0 = 1 rad. Measured at 1000 Hz: 4.7e-3 rad for both engines, the
// first-order error of their semi-implicit Euler step (about theta0 w h / 2 = 5.7e-3 rad); bound 0.01.
TEST_P(PeerTest, PendulumViscousFrictionFollowsTheReference) {
  vaw::dyn::PendulumScenario p;
  p.fr = 0.0005;
  const auto r = peer.pendulum(p, 1000, quick());
  const auto ref = vaw::dyn::pendulumReference(p);
  ASSERT_EQ(r.samples.size(), ref.size());
  EXPECT_LT(vaw::dyn::maxAbsDifference(r.samples, ref), 0.01);
  EXPECT_LT(std::abs(r.samples.back()), 0.02);  // reference: about 0.007 rad
}

TEST_P(PeerTest, SlideDeceleratesAndStops) {
  vaw::dyn::SlideScenario s;
  s.tiltDeg = 8.0;
  s.v0 = 1.5;
  const auto r = peer.slide(s, 1000, quick());
  ASSERT_EQ(r.samples.size(), vaw::dyn::slideReference(s).size());
  const auto at = [&](double t) { return r.samples[static_cast<std::size_t>(std::lround(t / kSampleInterval))]; };
  EXPECT_EQ(at(0.0), 0.0);
  EXPECT_GT(at(1.0), 0.0);
  EXPECT_LT(at(1.0), s.v0 * 1.0);                // decelerates
  EXPECT_NEAR(at(4.0), at(3.5), 0.005);          // stopped (the exact stop is at 2.6 s)
  const double exact = stopDistance(s);
  std::printf("[ %s ] slide at 1000 Hz: stop at %.6f m, exact %.6f m (%+.3f %%)\n", peer.name.c_str(), at(4.0), exact,
              100.0 * (at(4.0) / exact - 1.0));
  // Measured at 1000 Hz: ODE -0.04 % (dWorldStep is first order: about v0 dt / 2 = 0.75 mm), Bullet
  // -3.7 % (its sequential-impulse friction on a 3-4 point box-box manifold acts like mu = 0.203
  // instead of 0.2, and on an 8 degree slope with mu = 0.2 the deceleration g (mu cos - sin) is a
  // small difference, so 1.6 % in friction is 3.7 % in distance; -3.7 to -4.6 % from 90 to 1000 Hz).
  // Tolerances: 0.5 % for ODE, 6 % for Bullet and any other engine.
  const double tolerance = peer.name == "ode" ? 0.005 : 0.06;
  EXPECT_NEAR(at(4.0) / exact, 1.0, tolerance) << "stop " << at(4.0) << " m, exact " << exact << " m";
  EXPECT_GT(r.cpuPerSimSecond, 0.0);
  EXPECT_EQ(r.note.find("WARNING"), std::string::npos) << r.note;
}

// Sanity only (finite, timed); prints what the chart shows for this engine at every step rate: the
// errors against the references (default scenarios), the 5 degree period and the stop distance.
TEST_P(PeerTest, ReportErrorsAgainstReferences) {
  const vaw::dyn::SlideScenario s;
  vaw::dyn::PendulumScenario undamped, damped, small;
  damped.fr = 0.0005;
  small.theta0Deg = 5.0;
  const auto sRef = vaw::dyn::slideReference(s);
  const auto uRef = vaw::dyn::pendulumReference(undamped), dRef = vaw::dyn::pendulumReference(damped);
  for (int rate : vaw::dyn::kStepRates) {
    const auto a = peer.slide(s, rate, quick());
    const auto b = peer.pendulum(undamped, rate, quick());
    const auto c = peer.pendulum(damped, rate, quick());
    const auto d = peer.pendulum(small, rate, quick());
    std::printf("[ %s ] %4d Hz: slide err %.2e m, stop %+.2f %% (%.2e cpu s/s) | pendulum err %.2e rad (%.2e) | "
                "damped err %.2e rad (%.2e) | 5 deg period %+.3f %%\n",
                peer.name.c_str(), rate, vaw::dyn::maxAbsDifference(a.samples, sRef),
                100.0 * (a.samples.back() / stopDistance(s) - 1.0), a.cpuPerSimSecond,
                vaw::dyn::maxAbsDifference(b.samples, uRef), b.cpuPerSimSecond,
                vaw::dyn::maxAbsDifference(c.samples, dRef), c.cpuPerSimSecond,
                100.0 * (measuredPeriod(d.samples) / smallAmplitudePeriod(small) - 1.0));
    for (const auto* r : {&a, &b, &c, &d}) {
      EXPECT_EQ(r->samples.size(), r == &a ? sRef.size() : uRef.size());
      for (double x : r->samples) EXPECT_TRUE(std::isfinite(x));
      EXPECT_GT(r->cpuPerSimSecond, 0.0);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Engines, PeerTest, ::testing::ValuesIn(engineNames()),
                         [](const ::testing::TestParamInfo<std::string>& engine) { return engine.param; });

TEST(Peers, StepRateMustDivideTheSampleInterval) {
  EXPECT_EQ(vaw::peers::stepsPerSample(90), 9);
  EXPECT_EQ(vaw::peers::sampleCount(4.0), 41);
  EXPECT_THROW(vaw::peers::stepsPerSample(33), std::invalid_argument);
  EXPECT_THROW(vaw::peers::stepsPerSample(0), std::invalid_argument);
  for (const auto& p : vaw::peers::availablePeers())
    EXPECT_THROW(p.slide(vaw::dyn::SlideScenario{}, 45, quick()), std::invalid_argument) << p.name;
}

}  // namespace
