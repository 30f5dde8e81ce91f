#pragma once
// What the part-state inspector shows about one part, computed from the world (SI units; the UI only
// formats it): its state and how long it has been in it, who holds it, the model it moves by and the
// method that integrates it, the constraint it rests by, its model coordinates, its motion in the world
// with kinetic and potential energy, and its last transition and refusal.
#include <optional>
#include <string>

#include "vaw/sim/world.hpp"

namespace vaw::sim {

// Whether the rotation method and rate can integrate a part's swing (World::rotationStability), and what
// would make it safe: the lowest rate that keeps a margin of kSafeMargin with this method, or a method
// that is safe at this rate.
struct StabilityAdvice {
  static constexpr double kSafeMargin = 1.5;  // "near the limit" below this ratio of the limit to wn*dt
  enum class Level { Stable, NearLimit, Unstable };
  Level level = Level::Stable;
  dyn::StabilityReport report;
  std::optional<double> safeRate;         // Hz, a whole number
  std::optional<dyn::Method> safeMethod;  // at the current rate
  std::string text;                       // one line for the status bar and the inspector
};
std::optional<StabilityAdvice> stabilityAdvice(const World& world, PartId part);

struct PartReport {
  interact::PartState state = interact::PartState::Static;
  double timeInState = 0.0;  // s
  Holder holder = Holder::None;
  Model model = Model::None;
  std::string modelName;     // e.g. "slide on a plane", "free flight, torque-free rotation"
  std::string method;        // e.g. "closed form", "rk4 (rotation), closed form (slide)"
  std::string constraint;    // the constraint's name, when on the base
  // Model coordinates (meaningful for the model named).
  double angle = 0.0, omega = 0.0, slide = 0.0, slideRate = 0.0;  // rad, rad/s, m, m/s
  Eigen::Vector2d planePosition = Eigen::Vector2d::Zero(), planeVelocity = Eigen::Vector2d::Zero();  // m, m/s
  Eigen::Vector3d centreOfMass = Eigen::Vector3d::Zero();  // world, m
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();      // of the centre of mass, m/s (held: as released now)
  Eigen::Vector3d angularVelocity = Eigen::Vector3d::Zero();  // rad/s, world
  double kineticEnergy = 0.0;    // J, translation and rotation
  double potentialEnergy = 0.0;  // J, m g z of the centre of mass under standard gravity (z = 0: world origin)
  std::optional<TransitionRecord> lastTransition;
  std::optional<Refusal> lastRefusal;
  std::optional<StabilityAdvice> stability;  // parts that turn on a shaft
};

PartReport report(const World& world, PartId part);

// Kinetic energy (translation and rotation) of a part moving with centre-of-mass velocity v and angular
// velocity w (world), and m g z of its centre of mass under standard gravity, in J.
struct PartEnergy {
  double kinetic = 0.0, potential = 0.0;
};
PartEnergy energy(const Part& part, const Eigen::Isometry3d& pose, const Eigen::Vector3d& v, const Eigen::Vector3d& w);

std::string_view name(Holder h);  // "none", "left hand", "right hand", "both hands", "hoist"

}  // namespace vaw::sim
