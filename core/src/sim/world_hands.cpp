// Grabbing and letting go with the hands (INHAND), and what a released part does next: PLACED at its
// final pose, onto the base by a recognized constraint, or into free flight with the release velocity.
#include <algorithm>

#include "world_impl.hpp"
#include "vaw/units.hpp"

namespace vaw::sim {

using detail::angleOf;
using detail::fmt;
using vaw::kDeg;
using interact::Event;
using interact::PartState;

bool World::Impl::grabbable(PartId id) const {
  if (base && id == *base) return false;
  const PartState s = parts[id].state;
  return s != PartState::InHand && s != PartState::OnTool;
}

double World::Impl::reachTo(PartId id, const Eigen::Vector3d& at) const {
  return std::sqrt(collision.worldBounds(collision::ObjectId::part(id)).squaredExteriorDistance(at));
}

std::optional<PartId> World::Impl::nearest(const Eigen::Vector3d& at, double reach, bool forTool) const {
  std::optional<PartId> best;
  double bestD = std::numeric_limits<double>::infinity();
  for (PartId i = 0; i < parts.size(); ++i) {
    if (!grabbable(i)) continue;
    if (forTool && parts[i].state != PartState::Static && parts[i].state != PartState::OnBaseStatic &&
        parts[i].state != PartState::Placed)
      continue;
    if (reachTo(i, at) > reach) continue;
    const double d = (comWorld(i) - at).norm();
    if (d < bestD) {
      bestD = d;
      best = i;
    }
  }
  return best;
}

// The part a closing hand takes: the one it names (within reach), else the nearest within reach.
std::optional<PartId> World::Impl::handTarget(const HandInput& hand) const {
  if (!hand.target) return nearest(hand.pose.translation(), settings.grabReach, false);
  const PartId id = *hand.target;
  if (id >= parts.size() || !grabbable(id) || reachTo(id, hand.pose.translation()) > settings.grabReach) return std::nullopt;
  return id;
}

void World::Impl::hands(const Input& in) {
  const HandInput* hs[2] = {&in.left, &in.right};
  // Falling edges first: the part is let go where it was at the end of the last step.
  for (int k = 0; k < 2; ++k) {
    if (prevGrab[k] && !hs[k]->grab && held[k]) {
      const PartId id = *held[k];
      const Holder hd = parts[id].holder;
      held[0] = held[0] == id ? std::nullopt : held[0];
      held[1] = held[1] == id ? std::nullopt : held[1];
      // A two-hand part follows the left hand (the lead), so its velocity is the left hand's.
      letGo(id, false,
            hd == Holder::Both ? interact::Hands::Both : (k == 0 ? interact::Hands::Left : interact::Hands::Right),
            hs[hd == Holder::Both ? 0 : k]);
    }
  }
  for (int k = 0; k < 2; ++k) {
    if (!hs[k]->grab || prevGrab[k] || held[k]) continue;
    flush();  // grabbing reads every part's world bounds
    const auto target = handTarget(*hs[k]);
    if (!target) continue;
    const int o = 1 - k;
    const bool both = hs[o]->grab && !held[o] && handTarget(*hs[o]) == target;
    const interact::Hands which = both ? interact::Hands::Both : (k == 0 ? interact::Hands::Left : interact::Hands::Right);
    if (!fireEvent(*target, Event::Grab, which, both ? "both hands" : (k == 0 ? "left hand" : "right hand"))) continue;
    PartRuntime& r = parts[*target];
    PartModel& m = models[*target];
    r.holder = both ? Holder::Both : (k == 0 ? Holder::Left : Holder::Right);
    r.model = Model::Kinematic;
    r.constraint.reset();
    r.velocity.setZero();
    r.angularVelocity.setZero();
    held[k] = target;
    if (both) held[o] = target;
    const int lead = both ? 0 : k;
    m.offset = hs[lead]->pose.inverse() * r.pose;
    m.history.clear();
    m.history.push_back({t, comWorld(*target), Eigen::Quaterniond(r.pose.linear())});
  }
  for (int k = 0; k < 2; ++k) prevGrab[k] = hs[k]->grab;
}

void World::Impl::letGo(PartId id, bool tool, interact::Hands hands, const HandInput* hand) {
  flush(id);
  PartRuntime& r = parts[id];
  PartModel& m = models[id];
  r.holder = Holder::None;
  // Read once, here, for the release: kept on, every snapshot of the recording would carry it.
  const std::vector<interact::PoseSample> history = std::move(m.history);
  m.history = {};
  Eigen::Isometry3d snapped;
  if (atFinalPose(id, snapped)) {
    const Eigen::Isometry3d before = r.pose;
    if (fireEvent(id, Event::ReachedFinalLocation, hands,
                  fmt("%.6f m, %.4f deg from the final pose", (snapped.translation() - before.translation()).norm(),
                      angleOf(snapped.linear().transpose() * before.linear()) / kDeg))) {
      setPose(id, snapped);
      r.model = Model::None;
      m.inBase = basePose.inverse() * snapped;
      r.velocity.setZero();
      r.angularVelocity.setZero();
      return;
    }
  }
  if (const auto rec = recognize(id)) {
    if (fireEvent(id, Event::ConstraintRecognized, hands,
                  assembly.constraints[rec->constraint].name +
                      fmt(": %.6f m, %.4f deg from its mate", rec->distance, rec->angle / kDeg))) {
      setPose(id, rec->pose);
      enterOnBase(id, rec->constraint);
      // Put down on its mate at home (a shaft stood on its plate) it has nowhere to slide to.
      placeIfHome(id);
      return;
    }
  }
  if (tool) {
    if (fireEvent(id, Event::ToolDetach, hands, "hoist opened")) {
      r.model = Model::None;
      r.velocity.setZero();
    }
    return;
  }
  interact::Twist tw;
  std::string source;
  if (hand != nullptr && hand->velocity) {
    // The part moves rigidly with the hand: its centre of mass at the hand's pose, seen from the hand's origin.
    const Eigen::Vector3d lever = hand->pose.linear() * (m.offset * def(id).mass.centerOfMass);
    tw.angular = hand->velocity->angular;
    tw.linear = hand->velocity->linear + tw.angular.cross(lever);
    source = ", measured by the hand's tracker";
  } else {
    tw = interact::releaseVelocity(history, settings.release);
  }
  const std::string cause = fmt("v=(%.4f, %.4f, %.4f) m/s", tw.linear.x(), tw.linear.y(), tw.linear.z()) + source;
  if (!fireEvent(id, Event::Release, hands, cause)) return;
  if (r.state == PartState::InSpace) {
    enterFlight(id, tw.linear, tw.angular, t);
    stepFlight(id, t, endOfStep());
  } else {
    r.model = Model::None;
    r.velocity.setZero();
  }
}

}  // namespace vaw::sim
