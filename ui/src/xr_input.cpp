#include "vaw/ui/xr_input.hpp"

#include <algorithm>
#include <cmath>

namespace vaw::xr {

namespace {

Eigen::AlignedBox3d transformed(const Eigen::AlignedBox3d& box, const Eigen::Isometry3d& pose) {
  Eigen::AlignedBox3d out;
  for (int c = 0; c < 8 && !box.isEmpty(); ++c) out.extend(pose * box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c)));
  return out;
}

}  // namespace

HandMapper::HandMapper(const Assembly& assembly, InputSettings settings) : settings_(settings), base_(assembly.base) {
  if (base_ && assembly.parts[*base_].mesh) {
    baseBox_ = assembly.parts[*base_].mesh->bounds();
    baseLowest_ = transformed(baseBox_, assembly.parts[*base_].pose).min().z();
  }
}

void HandMapper::update(std::size_t k, const HandSample& sample) {
  HandState& h = hands_[k];
  h.velocity.reset();
  if (sample.source == HandSample::Source::None) return;
  const auto& j = sample.joints;
  if (sample.source == HandSample::Source::Controller) {
    h.mode = sample.select ? Mode::Controller : Mode::Open;
    h.pose = j[kPalm];
    if (sample.linearValid[kPalm] && sample.angularValid[kPalm])
      h.velocity = interact::Twist{sample.linear[kPalm], sample.angular[kPalm]};
    return;
  }
  const double gap = (j[kThumbTip].translation() - j[kIndexTip].translation()).norm();
  double curl = 0.0;
  for (int tip : {kMiddleTip, kRingTip, kLittleTip}) curl += (j[static_cast<std::size_t>(tip)].translation() - j[kPalm].translation()).norm();
  curl /= 3.0;
  if (h.mode == Mode::Controller) h.mode = Mode::Open;  // the controller was put down: the hand decides afresh
  switch (h.mode) {
    case Mode::Open:
      if (gap < settings_.pinchClose) h.mode = Mode::Pinch;
      else if (curl < settings_.gripClose) h.mode = Mode::Grip;
      break;
    case Mode::Pinch:
      if (gap > settings_.pinchOpen) h.mode = Mode::Open;
      break;
    case Mode::Grip:
      if (curl > settings_.gripOpen) h.mode = Mode::Open;
      break;
    case Mode::Controller:
      break;
  }
  h.pose = j[kPalm];
  if (h.mode == Mode::Grip) {
    if (sample.linearValid[kPalm] && sample.angularValid[kPalm])
      h.velocity = interact::Twist{sample.linear[kPalm], sample.angular[kPalm]};
  } else {
    h.pose.translation() = 0.5 * (j[kThumbTip].translation() + j[kIndexTip].translation());
    if (sample.linearValid[kThumbTip] && sample.linearValid[kIndexTip] && sample.angularValid[kPalm])
      h.velocity = interact::Twist{0.5 * (sample.linear[kThumbTip] + sample.linear[kIndexTip]), sample.angular[kPalm]};
  }
}

Eigen::Isometry3d HandMapper::liftedBase(const Eigen::Isometry3d& pose) const {
  Eigen::Isometry3d out = pose;
  if (!baseBox_.isEmpty()) out.pretranslate(Eigen::Vector3d(0.0, 0.0, std::max(0.0, baseLowest_ - transformed(baseBox_, pose).min().z())));
  return out;
}

sim::Input HandMapper::next(const HandsSample& hands, const sim::World& world, const sim::HoistInput& hoist) {
  const bool wasClosed[2] = {closed(0), closed(1)};
  const bool wasGrab[2] = {leftOnPart_, closed(1)};
  for (std::size_t k = 0; k < 2; ++k) update(k, hands.hands[k]);
  const bool left = closed(0), right = closed(1);

  if (!left) {
    leftOnPart_ = false;
    baseOffset_.reset();
  } else if (!wasClosed[0] && right && !world.held(1)) {
    leftOnPart_ = true;  // joining the right hand on a two-hand part
  } else if (!wasClosed[0] && base_) {
    const Eigen::AlignedBox3d box = transformed(baseBox_, world.basePose());
    if (!box.isEmpty() && std::sqrt(box.squaredExteriorDistance(hands_[0].pose.translation())) <= settings_.baseReach)
      baseOffset_ = hands_[0].pose.inverse() * world.basePose();
  }
  if (right && !wasClosed[1] && left && !baseOffset_ && !world.held(1)) leftOnPart_ = true;  // the left was there first

  sim::Input in;
  in.hoist = hoist;
  in.left.pose = hands_[0].pose;
  in.left.grab = leftOnPart_;
  in.right.pose = hands_[1].pose;
  in.right.grab = right;
  if (baseOffset_) in.base = liftedBase(hands_[0].pose * *baseOffset_);
  // A two-hand part leaves with its lead hand's velocity, so on any opening both hands carry theirs.
  if ((wasGrab[0] && !in.left.grab) || (wasGrab[1] && !in.right.grab)) {
    in.left.velocity = hands_[0].velocity;
    in.right.velocity = hands_[1].velocity;
  }
  return in;
}

}  // namespace vaw::xr
