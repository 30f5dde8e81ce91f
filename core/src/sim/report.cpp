#include "vaw/sim/report.hpp"

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
  const Eigen::Matrix3d R = r.pose.linear();
  const Eigen::Matrix3d I = R * p.mass.inertiaCm * R.transpose();
  out.kineticEnergy = 0.5 * p.mass.mass * out.velocity.squaredNorm() + 0.5 * out.angularVelocity.dot(I * out.angularVelocity);
  out.potentialEnergy = p.mass.mass * kStandardGravity * out.centreOfMass.z();
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
  return out;
}

}  // namespace vaw::sim
