// Free flight (INSPACE): the centre of mass on its closed-form parabola from the release, the orientation by
// the rotation model chosen at release, and the time of impact with anything in the way found along the
// step's motion.
#include <algorithm>

#include "vaw/collision/time_of_impact.hpp"
#include "world_impl.hpp"
#include "vaw/units.hpp"

namespace vaw::sim {

using detail::fmt;
using vaw::kDeg;
using interact::Event;

void World::Impl::enterFlight(PartId id, const Eigen::Vector3d& v, const Eigen::Vector3d& w, double t0) {
  PartRuntime& r = parts[id];
  PartModel& m = models[id];
  const Part& d = def(id);
  r.model = Model::Free;
  r.constraint.reset();
  m.clearing = false;
  r.velocity = v;
  r.angularVelocity = w;
  m.release = dyn::Release{t0, comWorld(id), v, Eigen::Quaterniond(r.pose.linear()), w};
  m.gFree = dyn::worldGravity() * settings.gravity.freeFlight;
  m.radius = collision.maxRadius(collision::ObjectId::part(id), d.mass.centerOfMass);
  // The flight time to the highest environment surface below the part.
  double zHit = -std::numeric_limits<double>::infinity();
  for (std::size_t e = 0; e < assembly.environment.size(); ++e) {
    // Not the default floor: a flight off the table chose its rotation model before there was one, and
    // recorded sessions replay so until the part reaches the floor.
    if (assembly.environment[e].implied) continue;
    const double top = collision.worldBounds(collision::ObjectId::environment(e)).max().z();
    if (top < m.release.position.z()) zHit = std::max(zHit, top);
  }
  double flight = std::isfinite(zHit) ? dyn::timeToHeight(m.release, m.gFree, zHit) : 2.0;
  if (!std::isfinite(flight)) flight = 2.0;
  const dyn::RotationChoice choice =
      dyn::chooseRotationModel(m.release, d.mass.inertiaCm, flight, h(), settings.rotationModelTolerance * kDeg);
  m.rotation = choice.model;
  m.torqueFree.reset();
  if (m.rotation == dyn::RotationModel::TorqueFree) m.torqueFree.emplace(m.release, d.mass.inertiaCm);
}

void World::Impl::stepFlight(PartId id, double t0, double t1) {
  flush(id);
  PartRuntime& r = parts[id];
  PartModel& m = models[id];
  const Eigen::Vector3d com = def(id).mass.centerOfMass;
  collision::Motion motion;
  std::optional<dyn::TorqueFree> next;
  if (m.rotation == dyn::RotationModel::ConstantOmega) {
    motion = collision::ballistic(m.release, m.gFree, com, t0, t1, m.radius);
  } else {
    next = *m.torqueFree;
    next->step(t1 - t0);
    const Eigen::Quaterniond q0 = m.torqueFree->orientation(), q1 = next->orientation();
    const dyn::Release rel = m.release;
    const Eigen::Vector3d g = m.gFree;
    const double span = t1 - t0;
    motion.pose = [rel, g, com, q0, q1, t0, span](double s) {
      const Eigen::Quaterniond q = q0.slerp((s - t0) / span, q1);
      Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
      pose.linear() = q.toRotationMatrix();
      pose.translation() = dyn::ballisticPosition(rel, g, s) - pose.linear() * com;
      return pose;
    };
    motion.s0 = t0;
    motion.s1 = t1;
    const double vMax = std::max(dyn::ballisticVelocity(rel, g, t0).norm(), dyn::ballisticVelocity(rel, g, t1).norm());
    const double wMax = std::max(m.torqueFree->omegaWorld().norm(), next->omegaWorld().norm());
    motion.speedBound = vMax + wMax * m.radius;
  }
  collision::MotionEvent ev = collision::timeOfImpact(collision, collision::ObjectId::part(id), motion);
  // Leaving a surface (slid off the base's edge or shaft): in contact at the step's start but free at its
  // end is a part separating, not an impact.
  if (ev.kind == collision::EventKind::Contact && ev.s <= motion.s0 &&
      !collision.colliding(collision::ObjectId::part(id), motion.pose(t1)).blocked)
    ev.kind = collision::EventKind::None;
  // Clearing the edge it slid off: meeting the base alone is passing its corner, not landing on it.
  bool overBase = false;
  if (m.clearing && ev.kind == collision::EventKind::Contact && assembly.base &&
      ev.other == collision::ObjectId::part(*assembly.base)) {
    const collision::ObjectId left = *ev.other;
    const collision::BlockResult end = collision.colliding(collision::ObjectId::part(id), motion.pose(t1));
    const bool onlyBase = std::all_of(end.contacts.begin(), end.contacts.end(),
                                      [&](const collision::Contact& c) { return c.a == left || c.b == left; });
    if (onlyBase) {
      ev.kind = collision::EventKind::None;
      overBase = end.blocked;
    }
  }
  m.clearing = overBase;
  if (ev.kind == collision::EventKind::Contact) {
    setPose(id, motion.pose(ev.s));
    const Eigen::Vector3d vHit = dyn::ballisticVelocity(m.release, m.gFree, ev.s);
    r.velocity.setZero();
    r.angularVelocity.setZero();
    r.model = Model::None;
    const bool floor = ev.other && ev.other->kind == collision::ObjectId::Kind::Environment &&
                       assembly.environment[ev.other->index].kind == "floor";
    fireEvent(id, Event::HitEnvironment, interact::Hands::None,
              (floor ? "on the floor: hit " : "hit ") + objectName(ev.other) + fmt(" at t=%.6f s, speed %.4f m/s", ev.s, vHit.norm()));
    return;
  }
  setPose(id, motion.pose(t1));
  r.velocity = dyn::ballisticVelocity(m.release, m.gFree, t1);
  if (next) {
    m.torqueFree = next;
    r.angularVelocity = next->omegaWorld();
  }
}

// ---- on the base ----

}  // namespace vaw::sim
