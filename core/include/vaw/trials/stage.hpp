#pragma once
// How one presentation of a trial's scenario is played: which bundled scene it needs, and the hands' and
// the base's inputs step by step, scripted from the scene's own poses. The script is the same for every
// scale, so two trials differ in the scale alone, and it is a function of the time since the world was
// reset, so a presentation plays the same at any frame rate. The workbench's trials panel plays it
// (docs/trials.md, "The trials panel"); tests/trials/test_stage.cpp checks each scenario's motion
// against its closed form.
//
// What each scenario scripts (times in s from the reset):
//   drop-from-hand         the right hand takes the part, holds it still, opens;
//   throw                  the same, then the hand tosses it up and forward at a fixed velocity;
//   slide-off-tilted-base  the hand puts the part on its mate on the base and lets go; the left hand lifts
//                          the base and tilts it about the y axis past the friction angle, so the part
//                          slides off the low (+x) edge and falls to the table;
//   gear-pendulum          the hand slides the part onto its shaft, turned so its centre of mass is off the
//                          vertical, and lets go: it swings about the shaft.
#include <Eigen/Geometry>
#include <string_view>

#include "vaw/assembly.hpp"
#include "vaw/dynamics/gravity.hpp"
#include "vaw/sim/world.hpp"
#include "vaw/trials/design.hpp"

namespace vaw::trials {

// The scale `scales` sets for `motion`, and `scales` with that one set to `scale`: how a trial's scale
// reaches the world.
double scaleFor(const dyn::GravityScales& scales, MotionKind motion);
dyn::GravityScales withScale(dyn::GravityScales scales, MotionKind motion, double scale);

class Stage {
 public:
  // The bundled scene (in the resource folder's scenes/) a scenario plays on.
  static std::string_view sceneFile(Scenario scenario);

  // The script for `scenario` on `assembly`, its part the first one that is not the base. Throws
  // vaw::InputError naming the scene when it lacks what the scenario needs (a part; for the slide a mate
  // constraint on a horizontal plane and a final pose; for the pendulum an insert constraint on a
  // horizontal shaft and a final pose).
  Stage(Scenario scenario, const Assembly& assembly);

  [[nodiscard]] Scenario scenario() const { return scenario_; }
  [[nodiscard]] PartId part() const { return part_; }
  // When the hand opens.
  [[nodiscard]] double releaseTime() const { return release_; }
  // Whether a participant in the headset plays the presentation with their own hand (take the part, let
  // it go or toss it) rather than watch the script: the drop and the throw.
  [[nodiscard]] bool participantActs() const;

  // Writes what the script drives for the step that ends at `t` into `in`: the right hand until it has
  // let go, and the base for the slide. What the script does not drive is left as it was, so a desktop
  // hand may still catch the part in flight.
  void script(double t, sim::Input& in) const;
  // The presentation is over `sinceRelease` s after the part left the hand: it has landed (drop, throw,
  // slide), swung for the watching time (pendulum), or a hand has taken it back; or it has run for its
  // longest time.
  [[nodiscard]] bool over(const sim::World& world, double sinceRelease) const;

  // A viewpoint that shows the whole motion at every scale from 0.05 to 2 (world, m); the same for every
  // trial, so the framing does not give the scale away.
  [[nodiscard]] const Eigen::Vector3d& eye() const { return eye_; }
  [[nodiscard]] const Eigen::Vector3d& centre() const { return centre_; }

  // The throw's release velocity (world, m/s) and the pendulum's release angle of the centre of mass from
  // hanging straight down (rad): what the tests compare the motion with.
  static const Eigen::Vector3d kThrowVelocity;
  static constexpr double kPendulumAngle = 0.7853981633974483;  // 45 degrees
  // The slide's final tilt of the base (rad), past the friction angle of any static coefficient up to 0.4.
  static constexpr double kSlideTilt = 0.4014257279586958;  // 23 degrees

 private:
  [[nodiscard]] Eigen::Isometry3d handPose(double t) const;
  [[nodiscard]] Eigen::Isometry3d basePose(double t) const;

  Scenario scenario_;
  PartId part_ = 0;
  PartId base_ = 0;
  Eigen::Isometry3d start_ = Eigen::Isometry3d::Identity();     // the part's pose at load
  Eigen::Isometry3d approach_ = Eigen::Isometry3d::Identity();  // pendulum: on the shaft's axis, off its end
  Eigen::Isometry3d placed_ = Eigen::Isometry3d::Identity();    // where the hand lets go
  Eigen::Isometry3d baseLoad_ = Eigen::Isometry3d::Identity();
  Eigen::Vector3d tiltPivot_ = Eigen::Vector3d::Zero();          // slide: the base's low edge
  double release_ = 0.0;
  Eigen::Vector3d eye_ = Eigen::Vector3d::Zero(), centre_ = Eigen::Vector3d::Zero();
};

}  // namespace vaw::trials
