#pragma once
// Hands that assemble in tests: a grab at the part's centre of mass, the part moved rigidly to a target,
// held still (so it leaves with no velocity) and let go; then the world left to settle.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <functional>
#include <string>

#include "vaw/assembly.hpp"
#include "vaw/sim/world.hpp"

namespace vaw::test {

class Assembler {
 public:
  explicit Assembler(const Assembly& a) : a_(a), w_(a, vaw::sim::settingsFor(a)) {}
  vaw::sim::World& world() { return w_; }
  // Called after every step the assembler runs (a session observer).
  std::function<void(const vaw::sim::World&)> afterStep;
  void carry(const std::string& part, const Eigen::Isometry3d& target) {
    const PartId id = *a_.findPart(part);
    const Eigen::Isometry3d from = w_.part(id).pose;
    Eigen::Isometry3d hand = Eigen::Isometry3d::Identity();
    hand.translation() = from * a_.parts[id].mass.centerOfMass;
    vaw::sim::Input in;
    in.right = {hand, true, std::nullopt};
    for (int i = 0; i < 5; ++i) step(in);
    ASSERT_EQ(w_.part(id).state, interact::PartState::InHand) << part;
    in.right.pose = target * from.inverse() * hand;
    for (int i = 0; i < 30; ++i) step(in);
    in.right.grab = false;
    step(in);
  }
  void settle(int steps = 300) {
    vaw::sim::Input in;
    for (int i = 0; i < steps; ++i) step(in);
  }
  interact::PartState state(const std::string& part) { return w_.part(*a_.findPart(part)).state; }
  std::string events(const std::string& part, bool causes = false) {
    std::string s;
    for (const auto& t : w_.transitions())
      if (a_.parts[t.part].name == part)
        s += std::string(s.empty() ? "" : " ") + std::string(vaw::interact::name(t.event)) + (causes ? " (" + t.cause + ")" : "");
    return s;
  }
  Eigen::Isometry3d above(const std::string& part, double mm) {
    Eigen::Isometry3d t = *a_.parts[*a_.findPart(part)].finalPose;
    t.translation().z() += mm * 1e-3;
    return t;
  }

 private:
  void step(const vaw::sim::Input& in) {
    w_.step(in);
    if (afterStep) afterStep(w_);
  }
  const Assembly& a_;
  vaw::sim::World w_;
};

}  // namespace vaw::test
