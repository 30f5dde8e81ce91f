#include "vaw/sim/report.hpp"

#include <cmath>
#include <cstdio>

#include "vaw/units.hpp"

namespace vaw::sim {

std::string_view name(Holder h) {
  switch (h) {
    case Holder::None: return "none";
    case Holder::Left: return "left hand";
    case Holder::Right: return "right hand";
    case Holder::Both: return "both hands";
    case Holder::Hoist: return "hoist";
  }
  return "?";
}

std::optional<StabilityAdvice> stabilityAdvice(const World& world, PartId id) {
  const auto report = world.rotationStability(id);
  if (!report) return std::nullopt;
  StabilityAdvice a;
  a.report = *report;
  const dyn::Method method = world.settings().rotationMethod;
  const double rate = world.settings().rate;
  if (!report->stable) a.level = StabilityAdvice::Level::Unstable;
  else if (report->margin < StabilityAdvice::kSafeMargin) a.level = StabilityAdvice::Level::NearLimit;
  const double wn = report->wnDt * rate;
  if (report->limitWnDt > 0.0 && wn > 0.0)
    a.safeRate = std::ceil(wn * StabilityAdvice::kSafeMargin / report->limitWnDt);
  // A method that is safe at this rate, the most accurate first; judged undamped, the conservative case.
  for (const dyn::Method m : {dyn::Method::RK4, dyn::Method::VelocityVerlet, dyn::Method::SemiImplicitEuler}) {
    if (m == method || !rotationSupports(m)) continue;
    const auto r = dyn::checkStability(m, wn, 0.0, 1.0 / rate);
    if (r.stable && r.margin >= StabilityAdvice::kSafeMargin) {
      a.safeMethod = m;
      break;
    }
  }
  char buf[320];
  const std::string mname(dyn::name(method));
  if (!(report->wnDt > 0.0) || !std::isfinite(report->margin)) {
    // No restoring torque, so no swing and no limit to be below: say so rather than print "infx".
    std::snprintf(buf, sizeof buf, "%s at %g Hz: nothing swings (gravity has no torque about this axis)", mname.c_str(), rate);
  } else if (a.level == StabilityAdvice::Level::Stable) {
    std::snprintf(buf, sizeof buf, "%s at %g Hz is stable for this swing (wn*dt %.3g, %.1fx below its limit)",
                  mname.c_str(), rate, report->wnDt, report->margin);
  } else {
    std::string fix;
    if (a.safeRate && (report->limitWnDt > 0.0)) fix = "a rate of " + std::to_string(static_cast<long long>(*a.safeRate)) + " Hz";
    if (a.safeMethod) fix += (fix.empty() ? "" : " or ") + std::string(dyn::name(*a.safeMethod)) + " at this rate";
    if (fix.empty()) fix = "another method";
    std::snprintf(buf, sizeof buf, "%s at %g Hz is %s for this swing (wn*dt %.3g, limit %.3g): the amplitude %s x%.3g per second; use %s",
                  mname.c_str(), rate, a.level == StabilityAdvice::Level::Unstable ? "UNSTABLE" : "near its stability limit",
                  report->wnDt, report->limitWnDt, report->growthPerSecond >= 1.0 ? "grows" : "changes", report->growthPerSecond,
                  fix.c_str());
  }
  a.text = buf;
  return a;
}

PartEnergy energy(const Part& p, const Eigen::Isometry3d& pose, const Eigen::Vector3d& v, const Eigen::Vector3d& w) {
  const Eigen::Matrix3d R = pose.linear();
  const Eigen::Matrix3d I = R * p.mass.inertiaCm * R.transpose();
  return {0.5 * p.mass.mass * v.squaredNorm() + 0.5 * w.dot(I * w), p.mass.mass * kStandardGravity * (pose * p.mass.centerOfMass).z()};
}

PartReport report(const World& world, PartId id) {
  const PartRuntime& r = world.part(id);
  const Part& p = world.assembly().parts[id];
  PartReport out;
  out.state = r.state;
  out.holder = r.holder;
  out.model = r.model;
  out.angle = r.angle;
  out.omega = r.omega;
  out.slide = r.slide;
  out.slideRate = r.slideRate;
  out.planePosition = r.planeP;
  out.planeVelocity = r.planeV;
  out.centreOfMass = r.pose * p.mass.centerOfMass;
  out.velocity = r.velocity;
  out.angularVelocity = r.angularVelocity;
  if (r.state == interact::PartState::InHand) {
    if (const auto tw = world.releaseVelocity(id)) {
      out.velocity = tw->linear;
      out.angularVelocity = tw->angular;
    }
  }
  const std::string rotation(dyn::name(world.settings().rotationMethod));
  switch (r.model) {
    case Model::None: out.modelName = "at rest (no model)"; break;
    case Model::Kinematic:
      out.modelName = r.holder == Holder::Hoist ? "carried by the hoist (kinematic)" : "held (kinematic)";
      break;
    case Model::Free: {
      const auto rot = world.flightRotation(id);
      out.modelName = std::string("free flight, ") +
                      (rot == dyn::RotationModel::TorqueFree ? "torque-free rotation" : "constant angular velocity");
      out.method = "closed-form parabola" + std::string(rot == dyn::RotationModel::TorqueFree ? ", rk4 rotation" : "");
      break;
    }
    case Model::Cylindrical:
      out.modelName = "rotation and slide on an axis";
      out.method = rotation + " (rotation), closed form (slide)";
      break;
    case Model::Plane:
      out.modelName = "slide on a plane";
      out.method = "closed form";
      break;
  }
  if (r.constraint) out.constraint = world.assembly().constraints[*r.constraint].name;
  const PartEnergy e = energy(p, r.pose, out.velocity, out.angularVelocity);
  out.kineticEnergy = e.kinetic;
  out.potentialEnergy = e.potential;
  for (auto it = world.transitions().rbegin(); it != world.transitions().rend(); ++it)
    if (it->part == id) {
      out.lastTransition = *it;
      break;
    }
  for (auto it = world.refusals().rbegin(); it != world.refusals().rend(); ++it)
    if (it->part == id) {
      out.lastRefusal = *it;
      break;
    }
  // Time in the state: since the end of the step it was entered in (the state lasts from there).
  out.timeInState = world.time() - (out.lastTransition ? out.lastTransition->t : 0.0);
  out.stability = stabilityAdvice(world, id);
  return out;
}

}  // namespace vaw::sim
