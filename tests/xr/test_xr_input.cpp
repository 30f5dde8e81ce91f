// The headset's hands as the world's input (ui/include/vaw/ui/xr_input.hpp): pinch and grip with hysteresis at the
// thresholds the settings give, the measured release velocity passed on unscaled, a hand the headset loses
// keeping what it held, the left hand holding the base.
#include <gtest/gtest.h>

#include "bundled.hpp"
#include "vaw/sim/world.hpp"
#include "vaw/ui/xr_input.hpp"

using vaw::xr::HandMapper;
using vaw::xr::HandSample;
using vaw::xr::HandsSample;
using vaw::xr::InputSettings;

namespace {

// A tracked hand at `at` (world): thumb and index tips `pinch` apart across the hand, the middle, ring and
// little tips `curl` from the palm.
HandSample hand(const Eigen::Vector3d& at, double pinch, double curl = 0.09) {
  HandSample h;
  h.source = HandSample::Source::Joints;
  for (auto& j : h.joints) j = Eigen::Isometry3d::Identity();
  for (auto& j : h.joints) j.translation() = at;
  h.joints[vaw::xr::kPalm].translation() = at + Eigen::Vector3d(0.0, 0.0, 0.06);
  h.joints[vaw::xr::kThumbTip].translation() = at + Eigen::Vector3d(0.5 * pinch, 0.0, 0.0);
  h.joints[vaw::xr::kIndexTip].translation() = at - Eigen::Vector3d(0.5 * pinch, 0.0, 0.0);
  for (int tip : {vaw::xr::kMiddleTip, vaw::xr::kRingTip, vaw::xr::kLittleTip})
    h.joints[static_cast<std::size_t>(tip)].translation() = h.joints[vaw::xr::kPalm].translation() + Eigen::Vector3d(0.0, 0.0, -curl);
  return h;
}

class XrInput : public ::testing::Test {
 protected:
  XrInput() : assembly_(vaw::test::loadBundled("block-on-plate.vaw.json")), world_(assembly_) {}
  vaw::sim::Input next(HandMapper& m, const HandSample& right, const HandSample& left = {}) {
    HandsSample s;
    s.hands[0] = left;
    s.hands[1] = right;
    return m.next(s, world_, {});
  }
  vaw::Assembly assembly_;
  vaw::sim::World world_;
  Eigen::Vector3d far_{0.0, -0.4, 0.3};  // away from every part and the base
};

TEST_F(XrInput, PinchClosesAndOpensAtItsThresholdsWithHysteresis) {
  HandMapper m(assembly_, InputSettings{});
  EXPECT_FALSE(next(m, hand(far_, 0.030)).right.grab) << "between the thresholds an open hand stays open";
  EXPECT_TRUE(next(m, hand(far_, 0.020)).right.grab) << "below 2.5 cm it closes";
  EXPECT_TRUE(next(m, hand(far_, 0.040)).right.grab) << "between the thresholds a closed hand stays closed";
  EXPECT_FALSE(next(m, hand(far_, 0.050)).right.grab) << "above 4.5 cm it opens";
  const auto in = next(m, hand(far_, 0.020));
  EXPECT_LT((in.right.pose.translation() - far_).norm(), 1e-12) << "a pinch holds at the point between the tips";
}

TEST_F(XrInput, ThresholdsComeFromTheSettings) {
  InputSettings s;
  s.pinchClose = 0.010;
  s.pinchOpen = 0.015;
  HandMapper m(assembly_, s);
  EXPECT_FALSE(next(m, hand(far_, 0.012)).right.grab);
  EXPECT_TRUE(next(m, hand(far_, 0.008)).right.grab);
  EXPECT_FALSE(next(m, hand(far_, 0.016)).right.grab);
}

TEST_F(XrInput, ClosedGripGrabsAtThePalm) {
  HandMapper m(assembly_, InputSettings{});
  const auto in = next(m, hand(far_, 0.08, 0.04));
  EXPECT_TRUE(in.right.grab);
  EXPECT_LT((in.right.pose.translation() - (far_ + Eigen::Vector3d(0.0, 0.0, 0.06))).norm(), 1e-12);
  EXPECT_TRUE(next(m, hand(far_, 0.08, 0.06)).right.grab) << "hysteresis: 6 cm is not yet open";
  EXPECT_FALSE(next(m, hand(far_, 0.08, 0.08)).right.grab);
}

TEST_F(XrInput, MeasuredVelocityGoesOutUnscaledOnTheOpeningStepOnly) {
  HandMapper m(assembly_, InputSettings{});
  HandSample closed = hand(far_, 0.02);
  const Eigen::Vector3d v(0.4, -0.2, 1.1), w(0.0, 0.0, 2.0);
  for (int j : {vaw::xr::kThumbTip, vaw::xr::kIndexTip, vaw::xr::kPalm}) {
    closed.linear[static_cast<std::size_t>(j)] = v;
    closed.angular[static_cast<std::size_t>(j)] = w;
    closed.linearValid[static_cast<std::size_t>(j)] = closed.angularValid[static_cast<std::size_t>(j)] = true;
  }
  EXPECT_FALSE(next(m, closed).right.velocity) << "no velocity while the hand stays closed";
  HandSample open = hand(far_, 0.06);
  open.linear = closed.linear;
  open.angular = closed.angular;
  open.linearValid = closed.linearValid;
  open.angularValid = closed.angularValid;
  const auto in = next(m, open);
  ASSERT_FALSE(in.right.grab);
  ASSERT_TRUE(in.right.velocity);
  EXPECT_EQ(in.right.velocity->linear, v) << "no throw boost";
  EXPECT_EQ(in.right.velocity->angular, w);
  EXPECT_FALSE(next(m, open).right.velocity);
}

TEST_F(XrInput, InvalidJointVelocitiesLeaveTheWorldsEstimate) {
  HandMapper m(assembly_, InputSettings{});
  (void)next(m, hand(far_, 0.02));
  HandSample open = hand(far_, 0.06);
  open.linear[vaw::xr::kThumbTip] = Eigen::Vector3d(9, 9, 9);  // flags not valid: not to be used
  const auto in = next(m, open);
  EXPECT_FALSE(in.right.grab);
  EXPECT_FALSE(in.right.velocity);
}

TEST_F(XrInput, AHandOutOfSightKeepsItsPoseAndWhatItHolds) {
  HandMapper m(assembly_, InputSettings{});
  (void)next(m, hand(far_, 0.02));
  const auto in = next(m, HandSample{});
  EXPECT_TRUE(in.right.grab);
  EXPECT_LT((in.right.pose.translation() - far_).norm(), 1e-12);
}

TEST_F(XrInput, ControllerSelectGrabsAtTheGripPose) {
  HandMapper m(assembly_, InputSettings{});
  HandSample c;
  c.source = HandSample::Source::Controller;
  c.joints[vaw::xr::kPalm] = Eigen::Isometry3d::Identity();
  c.joints[vaw::xr::kPalm].translation() = far_;
  EXPECT_FALSE(next(m, c).right.grab);
  c.select = true;
  const auto in = next(m, c);
  EXPECT_TRUE(in.right.grab);
  EXPECT_LT((in.right.pose.translation() - far_).norm(), 1e-12);
}

TEST_F(XrInput, LeftHandClosingAtTheBaseHoldsIt) {
  ASSERT_TRUE(assembly_.base);
  HandMapper m(assembly_, InputSettings{});
  const Eigen::Vector3d atBase = world_.basePose().translation();
  HandSample left = hand(atBase, 0.02);
  auto in = next(m, HandSample{}, left);
  EXPECT_TRUE(m.holdingBase());
  EXPECT_FALSE(in.left.grab) << "holding the base is not a grab of a part";
  ASSERT_TRUE(in.base);
  EXPECT_LT((in.base->translation() - atBase).norm(), 1e-12) << "no jump when the hand closes";
  left = hand(atBase + Eigen::Vector3d(0.0, 0.05, 0.10), 0.02);
  in = next(m, HandSample{}, left);
  ASSERT_TRUE(in.base);
  EXPECT_LT((in.base->translation() - (atBase + Eigen::Vector3d(0.0, 0.05, 0.10))).norm(), 1e-12) << "it follows the hand";
  in = next(m, HandSample{}, hand(atBase, 0.06));
  EXPECT_FALSE(m.holdingBase());
  EXPECT_FALSE(in.base);
}

}  // namespace
