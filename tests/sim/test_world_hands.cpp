// Hands, release and free flight (the paper's pictures of a part dropped or thrown from
// the hand). Tolerances: free flight is closed form, so positions match the closed form to 1e-9 m; a
// flight stops within the time-of-impact tolerance (10 um) of the table, asserted at 0.1 mm.
#include <gtest/gtest.h>

#include <cmath>

#include "sim_test_support.hpp"
#include "vaw/dynamics/free_flight.hpp"
#include "vaw/dynamics/gravity.hpp"

using namespace vaw;
using namespace vaw::sim;
using interact::PartState;
using simtest::at;

namespace {

// The block's lowest point (world z) from its mesh.
double lowestZ(const Assembly& a, PartId id, const Eigen::Isometry3d& pose) {
  double z = 1e300;
  for (const auto& v : a.parts[id].mesh->vertices) z = std::min(z, (pose * v).z());
  return z;
}

}  // namespace

// A part held still and let go falls straight down under the scaled gravity (0.25 g) and stops on the table.
TEST(WorldHands, DroppedPartFallsBallisticallyAndStopsOnTheTable) {
  const Assembly a = simtest::loadBundled("block-on-plate.vaw.json");
  const PartId block = *a.findPart("block");
  World w(a);
  const Eigen::Vector3d com0 = a.parts[block].pose * a.parts[block].mass.centerOfMass;
  const Eigen::Isometry3d handPose = at(com0.x(), com0.y(), com0.z());
  Input in;
  in.left = simtest::hand(handPose, true);
  for (int i = 0; i < 10; ++i) w.step(in);
  ASSERT_EQ(w.part(block).state, PartState::InHand);
  in.left.grab = false;
  w.step(in);
  ASSERT_EQ(w.part(block).state, PartState::InSpace);
  const double t0 = w.transitions().back().t - w.settings().step();  // released from the last held pose
  const Eigen::Vector3d g = dyn::worldGravity() * w.settings().gravity.freeFlight;
  double maxErr = 0.0;
  int steps = 0;
  while (w.part(block).state == PartState::InSpace && steps < 400) {
    const Eigen::Vector3d expected = com0 + 0.5 * g * (w.time() - t0) * (w.time() - t0);
    maxErr = std::max(maxErr, (w.part(block).pose * a.parts[block].mass.centerOfMass - expected).norm());
    w.step(in);
    ++steps;
  }
  RecordProperty("drop_max_error_m", simtest::num(maxErr));
  EXPECT_LT(maxErr, 1e-9) << "closed-form free flight";
  ASSERT_EQ(w.part(block).state, PartState::Static);
  EXPECT_EQ(simtest::join(simtest::transitionNames(w, block)), "grab:INHAND release:INSPACE hit-environment:STATIC");
  EXPECT_NE(w.transitions().back().cause.find("table"), std::string::npos) << w.transitions().back().cause;
  const double bottom = lowestZ(a, block, w.part(block).pose);
  RecordProperty("drop_rest_height_m", simtest::num(bottom));
  EXPECT_GE(bottom, 0.0);
  EXPECT_LT(bottom, 1e-4) << "stops on the table top (z = 0)";
  // Fall time against the closed form: sqrt(2 h / g_f).
  const double drop = lowestZ(a, block, a.parts[block].pose);
  const double tHit = std::sqrt(2.0 * drop / (0.25 * kStandardGravity));
  EXPECT_NEAR(w.transitions().back().t - t0, tHit, w.settings().step() + 1e-9);
  EXPECT_TRUE(w.refusals().empty());
}

// A throw: the hand moves at constant velocity; the windowed fit recovers it and the arc follows the closed form.
TEST(WorldHands, ThrownPartFollowsTheBallisticArcFromTheHandsVelocity) {
  const Assembly a = simtest::loadBundled("block-on-plate.vaw.json");
  const PartId block = *a.findPart("block");
  World w(a);
  const Eigen::Vector3d com0 = a.parts[block].pose * a.parts[block].mass.centerOfMass;
  const Eigen::Vector3d v(0.0, 0.2, 0.5);
  const double h = w.settings().step();
  Input in;
  int k = 0;
  for (; k < 20; ++k) {
    in.left = simtest::hand(at(com0.x(), com0.y(), com0.z()) * at(0, 0, 0), true);
    in.left.pose.translation() += v * (h * k);
    w.step(in);
  }
  in.left.grab = false;
  w.step(in);
  ASSERT_EQ(w.part(block).state, PartState::InSpace);
  const auto& rel = w.transitions().back();
  const double t0 = rel.t - h;
  const Eigen::Vector3d p0 = com0 + v * (h * (k - 1));
  EXPECT_LT((w.part(block).velocity - (v + dyn::worldGravity() * 0.25 * h)).norm(), 1e-9)
      << "release velocity from the windowed fit";
  const Eigen::Vector3d g = dyn::worldGravity() * 0.25;
  double maxErr = 0.0;
  while (w.part(block).state == PartState::InSpace && w.time() < 3.0) {
    const double dt = w.time() - t0;
    const Eigen::Vector3d expected = p0 + v * dt + 0.5 * g * dt * dt;
    maxErr = std::max(maxErr, (w.part(block).pose * a.parts[block].mass.centerOfMass - expected).norm());
    w.step(in);
  }
  RecordProperty("throw_max_error_m", simtest::num(maxErr));
  EXPECT_LT(maxErr, 1e-8);
  ASSERT_EQ(w.part(block).state, PartState::Static);
  EXPECT_LT(lowestZ(a, block, w.part(block).pose), 1e-4);
  EXPECT_GT(w.part(block).pose.translation().y(), 0.2) << "landed downrange";
}

// A tracked hand that measures its own velocity (a headset's hand joints): at release the part leaves with
// that velocity, carried rigidly to its centre of mass (v + w x r), not with what the windowed fit of its poses
// says, and nothing is scaled.
TEST(WorldHands, MeasuredHandVelocityIsTheReleaseVelocity) {
  const Assembly a = simtest::loadBundled("block-on-plate.vaw.json");
  const PartId block = *a.findPart("block");
  World w(a);
  const Eigen::Vector3d com0 = a.parts[block].pose * a.parts[block].mass.centerOfMass;
  const Eigen::Vector3d lever(0.0, -0.03, 0.02);  // the hand holds the block off its centre of mass
  const Eigen::Vector3d moved(0.0, 0.2, 0.5);     // how the poses move (what the fit would see)
  const double h = w.settings().step();
  Input in;
  for (int k = 0; k < 20; ++k) {
    in.left = simtest::hand(at(com0.x(), com0.y(), com0.z()) * at(-lever.x(), -lever.y(), -lever.z()), true);
    in.left.pose.translation() += moved * (h * k);
    w.step(in);
  }
  interact::Twist measured;
  measured.linear = Eigen::Vector3d(0.1, 0.0, 0.8);
  measured.angular = Eigen::Vector3d(0.0, 0.0, 0.5);  // about the vertical, a principal axis of the block
  const auto fitted = w.releaseVelocity(block);
  ASSERT_TRUE(fitted);
  EXPECT_LT((fitted->linear - moved).norm(), 1e-9) << "the fit follows the poses";
  in.left.grab = false;
  in.left.velocity = measured;
  w.step(in);
  ASSERT_EQ(w.part(block).state, PartState::InSpace);
  const Eigen::Vector3d expected = measured.linear + measured.angular.cross(lever) + dyn::worldGravity() * 0.25 * h;
  EXPECT_LT((w.part(block).velocity - expected).norm(), 1e-9) << "one step of flight after the measured release";
  EXPECT_LT((w.part(block).angularVelocity - measured.angular).norm(), 1e-9);
  EXPECT_NE(w.transitions().back().cause.find("measured by the hand's tracker"), std::string::npos)
      << w.transitions().back().cause;
}

// Released exactly at its final pose on the plate: PLACED, snapped, and it then rides with the base.
TEST(WorldHands, PartBroughtToItsFinalPoseEndsPlaced) {
  const Assembly a = simtest::loadBundled("block-on-plate.vaw.json");
  const PartId block = *a.findPart("block");
  World w(a);
  Input in;
  // Grab at the start pose, carry to 1 mm and 1 degree off the final pose over 1 s, let go.
  const Eigen::Isometry3d start = a.parts[block].pose;
  Eigen::Isometry3d target = *a.parts[block].finalPose;
  target.translation() += Eigen::Vector3d(0.001, 0.0, 0.0);
  target.linear() = Eigen::AngleAxisd(1.0 * M_PI / 180.0, Eigen::Vector3d::UnitZ()) * target.linear();
  for (int i = 0; i <= 90; ++i) {
    const double x = i / 90.0;
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.translation() = start.translation() + x * (target.translation() - start.translation());
    p.linear() = Eigen::Quaterniond(start.linear()).slerp(x, Eigen::Quaterniond(target.linear())).toRotationMatrix();
    in.left = simtest::hand(p, true);
    w.step(in);
  }
  in.left.grab = false;
  w.step(in);
  EXPECT_EQ(simtest::join(simtest::transitionNames(w, block)), "grab:INHAND reached-final-location:PLACED");
  EXPECT_TRUE(w.part(block).pose.isApprox(*a.parts[block].finalPose, 1e-12)) << "snapped to the final pose";
  // The base turns 20 degrees: the placed part turns with it, and stays PLACED.
  const Eigen::Isometry3d turn = simtest::rotAbout(Eigen::Vector3d::UnitX(), 20.0 * M_PI / 180.0, Eigen::Vector3d::Zero());
  in.base = turn * a.parts[*a.base].pose;
  for (int i = 0; i < 10; ++i) w.step(in);
  EXPECT_EQ(w.part(block).state, PartState::Placed);
  EXPECT_TRUE(w.part(block).pose.isApprox(turn * *a.parts[block].finalPose, 1e-12));
}

// Released near its mate (within 10 mm and 10 degrees) but not at its final pose: the constraint is
// recognized, the part is snapped onto the plate (keeping its free coordinates) and rests there.
TEST(WorldHands, PartReleasedNearItsMateIsPutOnTheBase) {
  const Assembly a = simtest::loadBundled("block-on-plate.vaw.json");
  const PartId block = *a.findPart("block");
  World w(a);
  Input in;
  Eigen::Isometry3d p = at(-0.05, -0.03, 0.055 + 0.006);  // 6 mm above the plate's top face
  p.linear() = Eigen::AngleAxisd(5.0 * M_PI / 180.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
  in.left = simtest::hand(a.parts[block].pose, true);
  w.step(in);
  in.left = simtest::hand(p, true);  // the hand jumps; the grab offset is identity (hand at the part's frame)
  w.step(in);
  in.left.grab = false;
  w.step(in);
  w.step(in);
  EXPECT_EQ(simtest::join(simtest::transitionNames(w, block)), "grab:INHAND constraint-recognized:ONBASESTATIC");
  const Eigen::Isometry3d& q = w.part(block).pose;
  EXPECT_NEAR(q.translation().z(), 0.055, 1e-9) << "on the plate's top face";
  EXPECT_NEAR((q.linear() * Eigen::Vector3d::UnitZ()).z(), 1.0, 1e-12) << "face down";
  EXPECT_NEAR(q.translation().x(), -0.05, 2e-3) << "free coordinates kept (up to the turn about the face point)";
}

// A part thrown spinning near its intermediate principal axis: the world picks torque-free rotation (the
// constant-omega model's predicted error exceeds 1 degree), the angular velocity wanders while the world
// angular momentum L = R I R^T w stays constant, and the part still stops on the table.
TEST(WorldHands, SpinningThrowUsesTorqueFreeRotationAndConservesAngularMomentum) {
  const Assembly a = simtest::loadBundled("block-on-plate.vaw.json");
  const PartId block = *a.findPart("block");
  World w(a);
  const Eigen::Isometry3d start = a.parts[block].pose;
  const Eigen::Vector3d omega = start.linear() * Eigen::Vector3d(0.2, 10.0, 0.2);  // about body y (intermediate)
  const Eigen::Vector3d v(0.0, 0.0, 1.0);
  const double h = w.settings().step();
  Input in;
  for (int k = 0; k < 20; ++k) {
    Eigen::Isometry3d p = start;
    p.linear() = Eigen::AngleAxisd(omega.norm() * h * k, omega.normalized()).toRotationMatrix() * start.linear();
    p.translation() = start.translation() + v * (h * k);
    in.left = simtest::hand(p, true);
    w.step(in);
  }
  in.left.grab = false;
  w.step(in);
  ASSERT_EQ(w.part(block).state, PartState::InSpace);
  const Eigen::Matrix3d I = a.parts[block].mass.inertiaCm;
  const auto L = [&](const PartRuntime& r) {
    const Eigen::Matrix3d R = r.pose.linear();
    return Eigen::Vector3d(R * I * R.transpose() * r.angularVelocity);
  };
  const Eigen::Vector3d L0 = L(w.part(block));
  const Eigen::Vector3d w0 = w.part(block).angularVelocity;
  // After one step of flight: the windowed fit's release spin, wandered by one torque-free step.
  EXPECT_LT((w0 - omega).norm(), 3e-3 * omega.norm()) << "release spin from the windowed fit";
  double maxLErr = 0.0, maxWander = 0.0;
  while (w.part(block).state == PartState::InSpace && w.time() < 3.0) {
    maxLErr = std::max(maxLErr, (L(w.part(block)) - L0).norm() / L0.norm());
    maxWander = std::max(maxWander, (w.part(block).angularVelocity - w0).norm());
    w.step(in);
  }
  RecordProperty("spin_angular_momentum_relative_error", simtest::num(maxLErr));
  RecordProperty("spin_omega_wander_rad_s", simtest::num(maxWander));
  EXPECT_LT(maxLErr, 1e-6) << "torque-free: world angular momentum conserved";
  EXPECT_GT(maxWander, 0.05) << "the angular velocity wanders (not the constant-omega model)";
  EXPECT_EQ(w.part(block).state, PartState::Static);
  EXPECT_EQ(simtest::join(simtest::transitionNames(w, block)), "grab:INHAND release:INSPACE hit-environment:STATIC");
}

// The capture hint the window shows while a part is carried: how far off its mate it is, and whether a
// release there goes onto it, which the release then does (or does not).
TEST(WorldHands, CaptureHintSaysWhetherAReleaseGoesOntoTheMate) {
  const Assembly a = simtest::loadBundled("sleeve-on-shaft.vaw.json");
  const PartId sleeve = *a.findPart("sleeve");
  for (const double off : {0.025, 0.003}) {
    World w(a);
    EXPECT_FALSE(w.captureHint(sleeve) && w.part(sleeve).state == PartState::InHand);
    const Eigen::Isometry3d start = a.parts[sleeve].pose;
    Eigen::Isometry3d target = *a.parts[sleeve].finalPose;
    target.translation() += Eigen::Vector3d(off, 0.0, 0.01);
    Input in;
    in.right = simtest::hand(start, true);
    w.step(in);
    in.right = simtest::hand(target, true);  // the hand's frame is the part's: it carries the part there
    for (int k = 0; k < 5; ++k) w.step(in);
    ASSERT_EQ(w.part(sleeve).state, PartState::InHand);
    const auto hint = w.captureHint(sleeve);
    ASSERT_TRUE(hint.has_value());
    EXPECT_EQ(hint->type, Constraint::Type::Insert);
    EXPECT_NEAR(hint->distance, off, 1e-9) << "off the shaft's axis";
    EXPECT_NEAR(hint->angle, 0.0, 1e-9);
    EXPECT_NEAR(std::abs(hint->direction.z()), 1.0, 1e-12) << "the shaft stands upright";
    const bool captures = off < w.settings().recognizeDistance;
    EXPECT_EQ(hint->captures, captures) << off;
    in.right.grab = false;
    w.step(in);
    const auto& log = w.transitions();
    const bool recognized = std::any_of(log.begin(), log.end(), [&](const auto& t) { return t.event == interact::Event::ConstraintRecognized; });
    EXPECT_EQ(recognized, captures) << "the release does what the hint said, " << off << " m off: "
                                    << simtest::join(simtest::transitionNames(w, sleeve));
  }
}
