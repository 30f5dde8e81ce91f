// Categories and tools: a tool-lifted part is refused to a hand and lifted by the hoist (vertical line plus
// yaw); a two-hand part needs both hands. Bundled scene hoist-demo.vaw.json.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "sim_test_support.hpp"
#include "vaw/units.hpp"

using namespace vaw;
using namespace vaw::sim;
using interact::PartState;
using simtest::at;

namespace {
using vaw::kDeg;

}  // namespace

TEST(WorldTools, ToolPartIsRefusedToAHandAndLiftedByTheHoistIntoItsPlace) {
  const Assembly a = simtest::loadBundled("hoist-demo.vaw.json");
  const PartId block = *a.findPart("block");
  ASSERT_EQ(a.parts[block].category.category, Category::Tool) << a.parts[block].category.reason;
  // The scene declares its hoist (version 2 "tools"): no settings needed.
  ASSERT_EQ(a.hoists.size(), 1u);
  EXPECT_EQ(a.hoists[0].position, Eigen::Vector2d(0.5, 0.0));
  World w(a);
  Input in;
  in.left = simtest::hand(a.parts[block].pose, true);
  w.step(in);
  ASSERT_EQ(w.refusals().size(), 1u);
  EXPECT_EQ(w.refusals()[0].part, block);
  EXPECT_EQ(w.refusals()[0].event, interact::Event::Grab);
  EXPECT_NE(w.refusals()[0].reason.find("only by a tool"), std::string::npos) << w.refusals()[0].reason;
  EXPECT_EQ(w.part(block).state, PartState::Static);
  in.left.grab = false;
  // The hook closes 22 mm above the block's top face and lifts it 0.3 m while turning 30 degrees.
  in.hoist = {true, 0.15, 0.0};
  w.step(in);
  ASSERT_EQ(w.part(block).state, PartState::OnTool);
  for (int i = 1; i <= 90; ++i) {
    in.hoist.height = 0.15 + 0.3 * i / 90.0;
    in.hoist.yaw = 30.0 * kDeg * i / 90.0;
    w.step(in);
  }
  const Eigen::Isometry3d& lifted = w.part(block).pose;
  EXPECT_NEAR(lifted.translation().z(), 0.064 + 0.3, 1e-12) << "follows the hook up";
  EXPECT_NEAR(lifted.translation().x(), 0.5, 1e-12) << "on the hoist's vertical line";
  EXPECT_NEAR(lifted.translation().y(), 0.0, 1e-12);
  EXPECT_NEAR(Eigen::AngleAxisd(lifted.linear()).angle(), 30.0 * kDeg, 1e-12) << "turned about the vertical";
  // The left hand brings the plate (the base) under the hook; the hoist turns back and lowers the block onto it.
  const Eigen::Isometry3d base0 = a.parts[*a.base].pose;
  for (int i = 1; i <= 90; ++i) {
    in.base = at(0.5 * i / 90.0, 0, 0) * base0;
    in.hoist.yaw = 30.0 * kDeg * (1.0 - i / 90.0);
    in.hoist.height = 0.45 - (0.45 - 0.19) * i / 90.0;
    w.step(in);
  }
  in.hoist.engaged = false;
  w.step(in);
  EXPECT_EQ(simtest::join(simtest::transitionNames(w, block)), "tool-attach:ONTOOL reached-final-location:PLACED");
  EXPECT_TRUE(w.part(block).pose.isApprox(*in.base * base0.inverse() * *a.parts[block].finalPose, 1e-12));
}

TEST(WorldTools, TwoHandPartNeedsBothHands) {
  const Assembly a = simtest::loadBundled("hoist-demo.vaw.json");
  const PartId tray = *a.findPart("tray");
  ASSERT_EQ(a.parts[tray].category.category, Category::TwoHand) << a.parts[tray].category.reason;
  World w(a);
  const Eigen::Isometry3d p = a.parts[tray].pose;
  Input in;
  in.left = simtest::hand(at(-0.1, 0, 0) * p, true);
  w.step(in);
  ASSERT_EQ(w.refusals().size(), 1u);
  EXPECT_NE(w.refusals()[0].reason.find("both hands"), std::string::npos) << w.refusals()[0].reason;
  EXPECT_EQ(w.part(tray).state, PartState::Static);
  in.right = simtest::hand(at(0.1, 0, 0) * p, true);  // the second hand closes while the first still holds
  w.step(in);
  ASSERT_EQ(w.part(tray).state, PartState::InHand);
  EXPECT_EQ(w.part(tray).holder, Holder::Both);
  for (int i = 1; i <= 20; ++i) {
    in.left.pose = at(-0.1, 0, 0.1 * i / 20.0) * p;
    in.right.pose = at(0.1, 0, 0.1 * i / 20.0) * p;
    w.step(in);
  }
  EXPECT_NEAR(w.part(tray).pose.translation().z(), p.translation().z() + 0.1, 1e-12);
  in.left.grab = false;
  w.step(in);
  w.step(in);
  EXPECT_EQ(simtest::join(simtest::transitionNames(w, tray)), "grab:INHAND release:STATIC");
  EXPECT_NEAR(w.part(tray).pose.translation().z(), p.translation().z() + 0.1, 1e-12) << "no dynamics: stays where released";
}
