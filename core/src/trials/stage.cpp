#include "vaw/trials/stage.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "vaw/error.hpp"

namespace vaw::trials {

const Eigen::Vector3d Stage::kThrowVelocity{0.0, 0.15, 1.0};

namespace {

// The hand holds the part still this long before it opens or throws: longer than the release estimator's
// 80 ms window, so a drop leaves the hand at rest whatever the estimator does.
constexpr double kHold = 0.4;
// The throw: constant acceleration up to kThrowVelocity, then that velocity for longer than the estimator's
// window, so the estimated release velocity is the scripted one.
constexpr double kThrowAccelerate = 0.2, kThrowCoast = 0.1;
// Carrying a part to where it is let go: smooth, and at rest on arrival.
constexpr double kTake = 0.2, kCarry = 1.0, kSlideOn = 0.7, kSettle = 0.3;
// The slide: the base rises this much, then tilts at the desktop's base rate.
constexpr double kLift = 0.25, kLiftTime = 0.8, kTiltRate = 30.0 * 3.14159265358979323846 / 180.0;
// The part is put down this far from its final pose within the mate's plane: beyond the place tolerance
// (recognized on its mate, not PLACED), and toward the base's high (-x) edge so it slides across it.
const Eigen::Vector3d kSlideOffset{-0.05, 0.005, 0.0};
// How long the pendulum is watched; the longest any presentation runs after the release.
constexpr double kSwingWatch = 6.0, kLongest = 20.0;
// Two steps at the slowest rate: the hand opens on the step after the script lets go.
constexpr double kOpening = 0.05;

double smooth(double s) {
  s = std::clamp(s, 0.0, 1.0);
  return s * s * (3.0 - 2.0 * s);
}

Eigen::Isometry3d between(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double s) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.linear() = Eigen::Quaterniond(a.linear()).slerp(s, Eigen::Quaterniond(b.linear())).toRotationMatrix();
  p.translation() = (1.0 - s) * a.translation() + s * b.translation();
  return p;
}

Eigen::Isometry3d rotationAbout(const Eigen::Vector3d& axis, double angle, const Eigen::Vector3d& pivot) {
  Eigen::Isometry3d r = Eigen::Isometry3d::Identity();
  r.linear() = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
  r.translation() = pivot - r.linear() * pivot;
  return r;
}

const Constraint* constraintOf(const Assembly& a, PartId part, Constraint::Type type) {
  for (const Constraint& c : a.constraints)
    if (c.part == part && c.type == type) return &c;
  return nullptr;
}

}  // namespace

double scaleFor(const dyn::GravityScales& scales, MotionKind motion) {
  switch (motion) {
    case MotionKind::FreeFlight: return scales.freeFlight;
    case MotionKind::Slide: return scales.slide;
    case MotionKind::Rotation: return scales.rotation;
  }
  return scales.freeFlight;
}

dyn::GravityScales withScale(dyn::GravityScales scales, MotionKind motion, double scale) {
  switch (motion) {
    case MotionKind::FreeFlight: scales.freeFlight = scale; break;
    case MotionKind::Slide: scales.slide = scale; break;
    case MotionKind::Rotation: scales.rotation = scale; break;
  }
  return scales;
}

std::string_view Stage::sceneFile(Scenario scenario) {
  switch (scenario) {
    case Scenario::DropFromHand:
    case Scenario::Throw: return "drop-from-hand.vaw.json";
    case Scenario::SlideOffTiltedBase: return "block-on-plate.vaw.json";
    case Scenario::GearPendulum: return "gear-on-shaft.vaw.json";
  }
  return {};
}

Stage::Stage(Scenario scenario, const Assembly& a) : scenario_(scenario) {
  const std::string file = a.source.string();
  const std::string what = "the " + std::string(name(scenario)) + " scenario's scene";
  bool found = false;
  for (PartId id = 0; id < a.parts.size() && !found; ++id)
    if (id != a.base) part_ = id, found = true;
  if (!found) fail(file, "parts", what + ": a part besides the base", "none");
  const Part& p = a.parts[part_];
  start_ = p.pose;
  placed_ = start_;
  const Eigen::Vector3d at = start_.translation();
  switch (scenario) {
    case Scenario::DropFromHand: {
      release_ = kHold;
      centre_ = Eigen::Vector3d(at.x(), at.y(), 0.5 * at.z());
      eye_ = centre_ + Eigen::Vector3d(0.0, -1.8 * at.z(), 0.2 * at.z());
      return;
    }
    case Scenario::Throw: {
      release_ = kHold + kThrowAccelerate + kThrowCoast;
      // Side on to the arc (which at a scale of 0.1 rises 0.5 m and lands 0.5 m ahead) and from above, from
      // the side away from the base, which would hide the landing.
      centre_ = Eigen::Vector3d(at.x(), at.y() + 0.3, 0.8 * at.z());
      eye_ = centre_ + Eigen::Vector3d(-2.4, -0.4, 1.1);
      return;
    }
    case Scenario::SlideOffTiltedBase:
    case Scenario::GearPendulum: break;
  }
  if (!a.base) fail(file, "base", what + ": a base part", "none");
  base_ = *a.base;
  baseLoad_ = a.parts[base_].pose;
  if (!p.finalPose) fail(file, "parts." + p.name + ".final_pose", what + ": the final pose the part is put near", "none");
  const Eigen::AlignedBox3d bounds = a.parts[base_].mesh ? a.parts[base_].mesh->bounds() : Eigen::AlignedBox3d();
  if (bounds.isEmpty()) fail(file, "parts." + a.parts[base_].name, what + ": a base with a shape", "none");
  Eigen::AlignedBox3d worldBounds;
  for (int c = 0; c < 8; ++c) worldBounds.extend(baseLoad_ * bounds.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c)));

  if (scenario == Scenario::SlideOffTiltedBase) {
    const Constraint* mate = constraintOf(a, part_, Constraint::Type::Mate);
    if (mate == nullptr || std::abs((baseLoad_.linear() * mate->basePlane.normal).z()) < std::cos(1e-3))
      fail(file, "constraints", what + ": a mate of \"" + p.name + "\" on a horizontal plane of the base", "none");
    placed_ = *p.finalPose;
    placed_.pretranslate(kSlideOffset);
    release_ = kTake + kCarry + kSettle;
    // About the base's bottom edge on its low (+x) side, so the base stays above where it was lifted from.
    tiltPivot_ = Eigen::Vector3d(worldBounds.max().x(), worldBounds.center().y(), worldBounds.min().z());
    // Side on to the tilt, from the raised base to where the part lands beyond its low edge.
    centre_ = Eigen::Vector3d(worldBounds.max().x() + 0.1, worldBounds.center().y(), worldBounds.max().z() + 0.4 * kLift);
    eye_ = centre_ + Eigen::Vector3d(0.3, -1.3, 0.35);
    return;
  }

  const Constraint* insert = constraintOf(a, part_, Constraint::Type::Insert);
  if (insert == nullptr)
    fail(file, "constraints", what + ": an insert of \"" + p.name + "\" on a shaft of the base", "none");
  const Eigen::Vector3d u = (baseLoad_.linear() * insert->baseAxis.direction).normalized();
  const Eigen::Vector3d axisPoint = baseLoad_ * insert->baseAxis.point;
  if (std::abs(u.z()) > 1e-3) fail(file, "constraints", what + ": a horizontal shaft", "one tilted from the horizontal");
  // The centre of mass's angle about the shaft from hanging straight down.
  const Eigen::Vector3d down(0.0, 0.0, -1.0), side = u.cross(down);
  Eigen::Vector3d r = *p.finalPose * p.mass.centerOfMass - axisPoint;
  r -= r.dot(u) * u;
  if (r.norm() < 1e-4)
    fail(file, "parts." + p.name, what + ": a part whose centre of mass is off the shaft's axis, so it swings", "on the axis");
  const double comAngle = std::atan2(r.dot(side), r.dot(down));
  placed_ = rotationAbout(u, kPendulumAngle - comAngle, axisPoint) * *p.finalPose;
  // Onto the shaft along its axis, from beyond the base's end on the part's side.
  const double sign = (placed_.translation() - worldBounds.center()).dot(u) >= 0.0 ? 1.0 : -1.0;
  double beyond = 0.0;
  for (int c = 0; c < 8; ++c)
    beyond = std::max(beyond, sign * (worldBounds.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c)) - placed_.translation()).dot(u));
  approach_ = placed_;
  approach_.pretranslate(sign * (beyond + p.extent) * u);
  release_ = kTake + kCarry + kSlideOn + kSettle;
  centre_ = placed_.translation();
  eye_ = centre_ + sign * 0.75 * u + Eigen::Vector3d(0.0, 0.0, 0.12);
}

bool Stage::participantActs() const { return scenario_ == Scenario::DropFromHand || scenario_ == Scenario::Throw; }

Eigen::Isometry3d Stage::handPose(double t) const {
  switch (scenario_) {
    case Scenario::DropFromHand: return start_;
    case Scenario::Throw: {
      const double tau = std::clamp(t - kHold, 0.0, kThrowAccelerate + kThrowCoast + kOpening);
      const double travel = tau < kThrowAccelerate ? 0.5 * tau * tau / kThrowAccelerate : tau - 0.5 * kThrowAccelerate;
      Eigen::Isometry3d p = start_;
      p.pretranslate(travel * kThrowVelocity);
      return p;
    }
    case Scenario::SlideOffTiltedBase: return between(start_, placed_, smooth((t - kTake) / kCarry));
    case Scenario::GearPendulum:
      if (t < kTake + kCarry) return between(start_, approach_, smooth((t - kTake) / kCarry));
      return between(approach_, placed_, smooth((t - kTake - kCarry) / kSlideOn));
  }
  return start_;
}

Eigen::Isometry3d Stage::basePose(double t) const {
  const double lifted = kLift * smooth((t - release_ - kSettle) / kLiftTime);
  const double tilt = std::clamp((t - release_ - 2.0 * kSettle - kLiftTime) * kTiltRate, 0.0, kSlideTilt);
  Eigen::Isometry3d pose = rotationAbout(Eigen::Vector3d::UnitY(), tilt, tiltPivot_) * baseLoad_;
  pose.pretranslate(Eigen::Vector3d(0.0, 0.0, lifted));
  return pose;
}

void Stage::script(double t, sim::Input& in) const {
  if (scenario_ == Scenario::SlideOffTiltedBase) in.base = basePose(t);
  if (t >= release_ + kOpening) return;
  const bool holding = t < release_;
  in.right = sim::HandInput{handPose(t), holding, holding ? std::optional<PartId>(part_) : std::nullopt};
}

bool Stage::over(const sim::World& world, double since) const {
  if (since <= kOpening) return false;
  if (since >= kLongest) return true;
  const sim::PartRuntime& p = world.part(part_);
  if (p.holder != sim::Holder::None) return true;  // taken back
  switch (scenario_) {
    case Scenario::DropFromHand:
    case Scenario::Throw: return p.state != interact::PartState::InSpace;
    case Scenario::SlideOffTiltedBase: return p.state == interact::PartState::Static;
    case Scenario::GearPendulum:
      return since >= kSwingWatch || p.state == interact::PartState::Static || p.state == interact::PartState::InSpace;
  }
  return true;
}

}  // namespace vaw::trials
