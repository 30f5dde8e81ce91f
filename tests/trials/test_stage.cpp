// Each trial scenario's script played on its bundled scene, headless, at two gravity scales: the motion the
// participant sees is the closed form at the trial's scale, and nothing else changes with the scale.
// Tolerances: times within 1.5 steps (the world reports contacts at step ends), the throw's release
// velocity within 1e-6 m/s (the estimator fits a constant velocity exactly), heights within 2 mm, the slide's
// acceleration and the swing's period within 1 %.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "bundled.hpp"
#include "vaw/error.hpp"
#include "vaw/sim/world.hpp"
#include "vaw/trials/stage.hpp"
#include "vaw/units.hpp"

using namespace vaw;
using interact::PartState;
using trials::Scenario;
using trials::Stage;

namespace {

using vaw::kDeg;

struct Played {
  std::vector<double> t, z, y, angle, planeSpeed;
  std::vector<PartState> state;
  std::optional<double> releasedAt, overAt;
  Eigen::Vector3d releaseVelocity = Eigen::Vector3d::Zero();
  std::string transitions;  // the states the part went through, in order
};

// Plays `stage` in a world whose scale for `motion` is `scale`, as the trials panel does: the script's
// input each step, the release taken from the part leaving the hand, until the stage says it is over.
Played play(const Assembly& a, const Stage& stage, trials::MotionKind motion, double scale) {
  sim::Settings settings = sim::settingsFor(a);
  settings.gravity = trials::withScale(settings.gravity, motion, scale);
  sim::World w(a, settings);
  Played out;
  sim::Input in;
  while (!out.overAt && w.time() < 40.0) {
    const double t = w.time() + settings.step();
    stage.script(t, in);
    const bool heldBefore = w.part(stage.part()).holder != sim::Holder::None;
    w.step(in);
    const sim::PartRuntime& p = w.part(stage.part());
    if (heldBefore && p.holder == sim::Holder::None && !out.releasedAt) {
      out.releasedAt = w.time();
      out.releaseVelocity = p.velocity;
    }
    out.t.push_back(w.time());
    out.z.push_back(p.pose.translation().z());
    out.y.push_back(p.pose.translation().y());
    out.angle.push_back(p.angle);
    out.planeSpeed.push_back(p.planeV.norm());
    out.state.push_back(p.state);
    if (out.releasedAt && stage.over(w, w.time() - *out.releasedAt)) out.overAt = w.time();
  }
  for (const auto& t : w.transitions())
    if (t.part == stage.part()) out.transitions += std::string(interact::name(t.to)) + " ";
  return out;
}

// The time the part first reached `state` after the release.
std::optional<double> firstTime(const Played& p, PartState state) {
  for (std::size_t i = 0; i < p.t.size(); ++i)
    if (p.releasedAt && p.t[i] > *p.releasedAt && p.state[i] == state) return p.t[i];
  return std::nullopt;
}

}  // namespace

TEST(Stage, EachScenarioHasItsBundledScene) {
  for (const Scenario s : {Scenario::DropFromHand, Scenario::Throw, Scenario::SlideOffTiltedBase, Scenario::GearPendulum}) {
    const Assembly a = test::loadBundled(std::string(Stage::sceneFile(s)));
    const Stage stage(s, a);
    EXPECT_NE(stage.part(), *a.base) << trials::name(s);
    EXPECT_GT(stage.releaseTime(), 0.3) << trials::name(s) << ": held still longer than the release window";
    EXPECT_GT((stage.eye() - stage.centre()).norm(), 0.5) << trials::name(s);
  }
}

// What the trials panel offers as bundled examples: each loads, and its scenario's script builds on its scene.
TEST(Stage, EveryBundledDesignPlaysOnItsScene) {
  int designs = 0;
  for (const auto& entry : std::filesystem::directory_iterator(test::resources() / "trials")) {
    if (!entry.path().string().ends_with(".vaw-trial.json")) continue;
    ++designs;
    const trials::Design d = trials::loadDesign(entry.path());
    const Assembly a = test::loadBundled(std::string(Stage::sceneFile(d.scenario)));
    EXPECT_NO_THROW(Stage(d.scenario, a)) << entry.path();
  }
  EXPECT_EQ(designs, 4) << "one bundled design per scenario";
}

TEST(Stage, ADropFallsItsHeightInTheTimeOfTheScaledGravity) {
  const Assembly a = test::loadBundled("drop-from-hand.vaw.json");
  const Stage stage(Scenario::DropFromHand, a);
  const double h = a.parts[stage.part()].pose.translation().z() - 0.015;  // the block's bottom above the table
  for (const double s : {0.25, 1.0}) {
    const Played p = play(a, stage, trials::MotionKind::FreeFlight, s);
    ASSERT_TRUE(p.releasedAt && p.overAt) << s;
    // At the end of the step it was let go in: at rest, then one step of the scaled gravity.
    EXPECT_LT((p.releaseVelocity - Eigen::Vector3d(0.0, 0.0, -s * kStandardGravity / 90.0)).norm(), 1e-9) << "let go at rest";
    const auto landed = firstTime(p, PartState::Static);
    ASSERT_TRUE(landed) << s;
    const double expected = std::sqrt(2.0 * h / (s * kStandardGravity));
    RecordProperty("drop_fall_time_s_at_" + std::to_string(s), std::to_string(*landed - *p.releasedAt));
    EXPECT_NEAR(*landed - *p.releasedAt, expected, 1.5 / 90.0) << "scale " << s;
    EXPECT_NEAR(*p.overAt, *landed, 1.5 / 90.0) << "over when it has landed";
  }
}

TEST(Stage, AThrowLeavesTheHandAtItsVelocityAndRisesToTheScaledApex) {
  const Assembly a = test::loadBundled("drop-from-hand.vaw.json");
  const Stage stage(Scenario::Throw, a);
  const Eigen::Vector3d v = Stage::kThrowVelocity;
  for (const double s : {0.25, 1.0}) {
    const Played p = play(a, stage, trials::MotionKind::FreeFlight, s);
    ASSERT_TRUE(p.releasedAt && p.overAt) << s;
    const double g = s * kStandardGravity;
    // At the end of the step it was let go in: the scripted velocity, then one step of the scaled gravity.
    const Eigen::Vector3d v1 = v - Eigen::Vector3d(0.0, 0.0, g / 90.0);
    EXPECT_LT((p.releaseVelocity - v1).norm(), 1e-6) << "released at " << p.releaseVelocity.transpose();
    std::size_t r = 0;
    while (p.t[r] < *p.releasedAt) ++r;
    const double z0 = p.z[r], y0 = p.y[r];
    double apex = z0;
    for (std::size_t i = r; i < p.z.size(); ++i) apex = std::max(apex, p.z[i]);
    EXPECT_NEAR(apex - z0, v1.z() * v1.z() / (2.0 * g), 0.002) << "scale " << s;
    // Lands where the parabola meets the table top (the block's bottom 15 mm below its centre).
    const double drop = z0 - 0.015;
    const double flight = (v1.z() + std::sqrt(v1.z() * v1.z() + 2.0 * g * drop)) / g;
    const auto landed = firstTime(p, PartState::Static);
    ASSERT_TRUE(landed) << "landed on the table at scale " << s;
    EXPECT_NEAR(*landed - *p.releasedAt, flight, 1.5 / 90.0) << "scale " << s;
    const std::size_t l = static_cast<std::size_t>(std::lower_bound(p.t.begin(), p.t.end(), *landed) - p.t.begin());
    EXPECT_NEAR(p.y[l] - y0, v.y() * (*landed - *p.releasedAt), 0.01) << "travelled ahead at the release's speed";
  }
}

TEST(Stage, TheTiltedBaseSlidesThePartOffWithTheScaledAcceleration) {
  const Assembly a = test::loadBundled("block-on-plate.vaw.json");
  const Stage stage(Scenario::SlideOffTiltedBase, a);
  const double muS = 0.3, muK = 0.2;
  const double tiltStart = stage.releaseTime() + 0.3 + 0.8 + 0.3, tiltDone = tiltStart + Stage::kSlideTilt / (30.0 * kDeg);
  for (const double s : {0.25, 1.0}) {
    const Played p = play(a, stage, trials::MotionKind::Slide, s);
    ASSERT_TRUE(p.releasedAt && p.overAt) << s;
    EXPECT_EQ(p.transitions, "INHAND ONBASESTATIC ONBASESLIDE INSPACE STATIC ") << "scale " << s;
    const auto startedAt = firstTime(p, PartState::OnBaseSlide);
    ASSERT_TRUE(startedAt);
    // Starts when the ramp passes the friction angle, whatever the scale (both sides scale with g).
    EXPECT_NEAR((*startedAt - tiltStart) * 30.0 * kDeg, std::atan(muS), 30.0 * kDeg / 90.0 * 1.5) << "scale " << s;
    std::vector<double> ts, speeds;  // sliding on the fully tilted base
    for (std::size_t i = 0; i < p.t.size(); ++i)
      if (p.state[i] == PartState::OnBaseSlide && p.t[i] > tiltDone + 2.0 / 90.0) {
        ts.push_back(p.t[i]);
        speeds.push_back(p.planeSpeed[i]);
      }
    ASSERT_GE(speeds.size(), 10u) << "slid on the fully tilted base for a while";
    const double measured = (speeds.back() - speeds.front()) / (ts.back() - ts.front());
    const double expected = s * kStandardGravity * (std::sin(Stage::kSlideTilt) - muK * std::cos(Stage::kSlideTilt));
    RecordProperty("slide_acceleration_at_" + std::to_string(s), std::to_string(measured));
    EXPECT_NEAR(measured / expected, 1.0, 0.01) << "scale " << s;
    EXPECT_LT(p.z.back(), 0.05) << "on the table";
  }
}

TEST(Stage, ThePendulumSwingsWithThePeriodOfTheScaledGravity) {
  const Assembly a = test::loadBundled("gear-on-shaft.vaw.json");
  const Stage stage(Scenario::GearPendulum, a);
  const Part& g = a.parts[stage.part()];
  const Eigen::Vector3d u = Eigen::Vector3d::UnitX(), axisPoint(0.0, 0.0, 0.15);
  const Eigen::Vector3d com = *g.finalPose * g.mass.centerOfMass - axisPoint;
  const double d = std::hypot(com.y(), com.z());
  const Eigen::Vector3d uPart = g.finalPose->linear().transpose() * u;
  const double J = uPart.dot(g.mass.inertiaCm * uPart) + g.mass.mass * d * d;
  const double fr = 0.0005;
  for (const double s : {0.25, 1.0}) {
    const Played p = play(a, stage, trials::MotionKind::Rotation, s);
    ASSERT_TRUE(p.releasedAt && p.overAt) << s;
    EXPECT_NEAR(*p.overAt - *p.releasedAt, 6.0, 1.5 / 90.0) << "watched for a fixed time";
    // phi: the centre of mass's angle from hanging down; the hinge angle is 0 at the release.
    std::vector<double> crossings, peaks;
    double peak = 0.0;
    for (std::size_t i = 1; i < p.t.size(); ++i) {
      if (p.t[i - 1] < *p.releasedAt || p.state[i] != PartState::OnBaseSlide) continue;
      const double a0 = Stage::kPendulumAngle + p.angle[i - 1], a1 = Stage::kPendulumAngle + p.angle[i];
      peak = std::max(peak, std::abs(a1));
      if (a0 > 0.0 && a1 <= 0.0) {
        crossings.push_back(p.t[i - 1] + (p.t[i] - p.t[i - 1]) * a0 / (a0 - a1));
        peaks.push_back(peak);
        peak = 0.0;
      }
    }
    ASSERT_GE(crossings.size(), 3u) << "several swings in the watching time at scale " << s;
    const double w0 = std::sqrt(g.mass.mass * s * kStandardGravity * d / J);
    const double zeta = fr / (2.0 * J * w0);
    for (std::size_t c = 1; c < crossings.size(); ++c) {
      const double expected = 4.0 / w0 * std::comp_ellint_1(std::sin(peaks[c] / 2.0)) / std::sqrt(1.0 - zeta * zeta);
      EXPECT_NEAR((crossings[c] - crossings[c - 1]) / expected, 1.0, 0.01) << "scale " << s << ", cycle " << c;
    }
    EXPECT_NEAR(peaks.front(), Stage::kPendulumAngle, 3.0 * kDeg) << "released 45 degrees from hanging";
  }
}

TEST(Stage, AScenesLackingWhatTheScenarioNeedsIsNamed) {
  const Assembly drop = test::loadBundled("drop-from-hand.vaw.json");
  try {
    Stage(Scenario::GearPendulum, drop);
    FAIL() << "a scene without a shaft was taken for the pendulum";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("drop-from-hand.vaw.json"), std::string::npos) << what;
    EXPECT_NE(what.find("final_pose"), std::string::npos) << what;
  }
  const Assembly plate = test::loadBundled("block-on-plate.vaw.json");
  try {
    Stage(Scenario::GearPendulum, plate);
    FAIL() << "a mate was taken for a shaft";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("an insert of \"block\" on a shaft"), std::string::npos) << e.what();
  }
}
