// Parts on the base: recognizing a released part's constraint near its mate (or its final pose), and the
// on-base models: the slide on a plane, the slide and rotation on an axis (ONBASESLIDE), with the touching
// and blocked checks along each step's motion, and the start test of a part at rest (ONBASESTATIC).
#include <algorithm>
#include <cstdint>
#include <limits>
#include <utility>

#include "vaw/collision/time_of_impact.hpp"
#include "world_impl.hpp"
#include "vaw/units.hpp"

namespace vaw::sim {

using detail::angleOf;
using detail::fmt;
using vaw::kDeg;
using interact::Event;
using interact::PartState;

namespace {

// Rotates `pose` about the world point `pivot` so that world direction `from` turns onto `to`.
Eigen::Isometry3d turnAbout(const Eigen::Isometry3d& pose, const Eigen::Vector3d& pivot, const Eigen::Vector3d& from,
                            const Eigen::Vector3d& to) {
  const Eigen::Matrix3d r = Eigen::Quaterniond::FromTwoVectors(from, to).toRotationMatrix();
  Eigen::Isometry3d out = pose;
  out.linear() = r * pose.linear();
  out.translation() = pivot + r * (pose.translation() - pivot);
  return out;
}

// The fraction of a step's straight path (in the model's coordinates, from (s0, p0) to (s1, p1)) that stays
// inside the free motion, from its start: 1 when all of it does, 0 when its start is outside; and what
// bounds the free motion where the path leaves it.
using Bound = collision::FreeMotion::Bound;
std::pair<double, Bound> freeFraction(const PartModel::Free& f, Model model, double s0, double s1,
                                      const Eigen::Vector2d& p0, const Eigen::Vector2d& p1) {
  const collision::FreeMotion& fm = f.motion;
  if (model == Model::Cylindrical) {
    const double d0 = s0 - f.slide, d1 = s1 - f.slide;
    if (!(d0 >= fm.axialMin && d0 <= fm.axialMax)) return {0.0, Bound::Conservative};
    if (d1 >= fm.axialMin && d1 <= fm.axialMax) return {1.0, Bound::Conservative};
    const bool up = d1 > fm.axialMax;
    return {((up ? fm.axialMax : fm.axialMin) - d0) / (d1 - d0), up ? fm.atMax : fm.atMin};
  }
  // Plane: the path from q0 to q1 leaves the disc of the free radius where |q0 + x (q1 - q0)| = radius.
  const Eigen::Vector2d q0 = p0 - f.planeP, dq = p1 - p0;
  const double r2 = fm.radius * fm.radius;
  if (!(q0.squaredNorm() < r2)) return {0.0, Bound::Conservative};
  if ((q0 + dq).squaredNorm() < r2) return {1.0, Bound::Conservative};
  const double a = dq.squaredNorm(), b = q0.dot(dq), c = q0.squaredNorm() - r2;
  return {std::clamp((-b + std::sqrt(b * b - a * c)) / a, 0.0, 1.0), fm.atMax};
}

}  // namespace

// A bore with clearance rests on the side of its shaft that gravity pulls it to: its axis lies `clearance`
// off the shaft's, along gravity's part across the axis (base frame). The slide's normal force is that same
// part of gravity (dyn::splitGravity), so the friction is the contact's. With gravity along the axis there
// is no such side, and the part stays where it was.
void World::Impl::updatePlay(PartId id) {
  PartModel& m = models[id];
  if (m.clearance <= 0.0 || !m.hinge) {
    m.play.setZero();
    return;
  }
  const Eigen::Vector3d u = m.hinge->axisInBase();
  Eigen::Vector3d g = basePose.linear().transpose() * gravity(settings.gravity.slide);
  g -= u * u.dot(g);
  if (g.norm() <= 1e-9 * kStandardGravity) return;
  m.play = g.normalized() * m.clearance;
}

World::Impl::Recognition World::Impl::measure(PartId id, std::size_t ci) const {
  const Eigen::Isometry3d& P = parts[id].pose;
  const Eigen::Isometry3d& B = basePose;
  const Constraint& c = inBaseFrame[ci];
  Recognition rec;
  rec.constraint = ci;
  if (c.type == Constraint::Type::Insert) {
    const Eigen::Vector3d dp = P.linear() * c.partAxis.direction, pp = P * c.partAxis.point;
    const Eigen::Vector3d db = B.linear() * c.baseAxis.direction, pb = B * c.baseAxis.point;
    const double dot = dp.dot(db);
    rec.angle = std::acos(std::clamp(std::abs(dot), 0.0, 1.0));
    const Eigen::Vector3d target = dot >= 0.0 ? db : Eigen::Vector3d(-db);
    rec.pose = turnAbout(P, pp, dp, target);
    const Eigen::Vector3d rel = pp - pb;
    const Eigen::Vector3d off = rel - db * db.dot(rel);
    rec.distance = off.norm();
    rec.pose.translation() -= off;
  } else {
    const Eigen::Vector3d np = P.linear() * c.partPlane.normal, pp = P * c.partPlane.point;
    const Eigen::Vector3d nb = B.linear() * c.basePlane.normal, pb = B * c.basePlane.point;
    const Eigen::Vector3d target = c.type == Constraint::Type::Mate ? Eigen::Vector3d(-nb) : nb;
    rec.angle = std::acos(std::clamp(np.dot(target), -1.0, 1.0));
    rec.pose = turnAbout(P, pp, np, target);
    const double d = nb.dot(pp - pb) - c.offset;
    rec.distance = std::abs(d);
    rec.pose.translation() -= nb * d;
  }
  return rec;
}

bool World::Impl::captures(PartId id, const Recognition& rec, bool checkTouch) {
  if (rec.angle > settings.recognizeAngle * kDeg || rec.distance > settings.recognizeDistance) return false;
  const Constraint& c = inBaseFrame[rec.constraint];
  // A constraint found in a CAD file knows the side its part comes home from: a part past its home
  // (a stud pushed through the plate from below) is not put on it there.
  if (c.found && def(id).finalPose) {
    const Eigen::Vector3d home = basePose.linear() * c.homeDirection;
    // Centres of mass, not frame origins: a nut carried the other way up (the same nut) has its frame's
    // origin at its other end.
    const Eigen::Vector3d& com = def(id).mass.centerOfMass;
    const Eigen::Vector3d finalAt = (basePose * (baseLoad.inverse() * *def(id).finalPose)) * com;
    // Where it was let go, not where the mate would snap it.
    if (home.dot(parts[id].pose * com - finalAt) < -settings.placeDistance) return false;
  }
  const collision::Support& s = scene->support(rec.constraint);
  if (!s.problem.empty()) return false;
  return !checkTouch || collision.touching(s, rec.pose).touching;
}

std::optional<World::Impl::Recognition> World::Impl::recognize(PartId id) {
  if (!base) return std::nullopt;
  for (std::size_t ci = 0; ci < inBaseFrame.size(); ++ci) {
    if (inBaseFrame[ci].part != id) continue;
    const Recognition rec = measure(id, ci);
    if (captures(id, rec)) return rec;
  }
  return std::nullopt;
}

std::optional<CaptureHint> World::Impl::captureHint(PartId id) {
  if (!base || id >= parts.size()) return std::nullopt;
  std::optional<CaptureHint> best;
  double bestScore = std::numeric_limits<double>::infinity();
  for (std::size_t ci = 0; ci < inBaseFrame.size(); ++ci) {
    const Constraint& c = inBaseFrame[ci];
    if (c.part != id || (c.partner && parts[*c.partner].state != PartState::Placed)) continue;
    const Recognition rec = measure(id, ci);
    // Nearest in units of the capture's own limits.
    const double score = rec.distance / settings.recognizeDistance + rec.angle / (settings.recognizeAngle * kDeg);
    if (score >= bestScore) continue;
    bestScore = score;
    CaptureHint h;
    h.constraint = ci;
    h.type = c.type;
    h.distance = rec.distance;
    h.angle = rec.angle;
    // Not flushed for a question between steps (that would make the world's state depend on who asked):
    // a partner whose pose the collision world does not have yet is not checked for touch.
    h.captures = captures(id, rec, !(c.partner && dirty[*c.partner]));
    if (c.type == Constraint::Type::Insert) {
      h.direction = basePose.linear() * c.baseAxis.direction;
      const Eigen::Vector3d pb = basePose * c.baseAxis.point;
      const Eigen::Vector3d pp = parts[id].pose * c.partAxis.point;
      h.point = pb + h.direction * h.direction.dot(pp - pb);
    } else {
      h.direction = basePose.linear() * c.basePlane.normal;
      const Eigen::Vector3d pb = basePose * c.basePlane.point;
      const Eigen::Vector3d pp = parts[id].pose * c.partPlane.point;
      h.point = pp - h.direction * (h.direction.dot(pp - pb) - c.offset);
    }
    best = h;
  }
  return best;
}

bool World::Impl::atFinalPose(PartId id, Eigen::Isometry3d& snapped) const {
  const Part& d = def(id);
  if (!base || !d.finalPose) return false;
  const Eigen::Isometry3d finalInBase = baseLoad.inverse() * *d.finalPose;
  const Eigen::Isometry3d nowInBase = basePose.inverse() * parts[id].pose;
  const double dist = (finalInBase.translation() - nowInBase.translation()).norm();
  const double ang = angleOf(finalInBase.linear().transpose() * nowInBase.linear());
  if (dist > settings.placeDistance || ang > settings.placeAngle * kDeg) return false;
  snapped = basePose * finalInBase;
  return true;
}

void World::Impl::enterOnBase(PartId id, std::size_t ci) {
  PartRuntime& r = parts[id];
  PartModel& m = models[id];
  const Constraint& c = inBaseFrame[ci];
  const Part& d = def(id);
  r.constraint = ci;
  r.angle = r.omega = r.slide = r.slideRate = 0.0;
  r.planeP.setZero();
  r.planeV.setZero();
  r.velocity.setZero();
  r.angularVelocity.setZero();
  m.sliding = false;
  m.blockedDir.setZero();
  m.blockedRot = 0.0;
  m.free.valid = false;
  m.inBase = basePose.inverse() * r.pose;
  if (c.type == Constraint::Type::Insert) {
    m.hinge = dyn::Hinge::make(c.baseAxis.point, c.baseAxis.direction, m.inBase, d.mass.mass, d.mass.centerOfMass,
                               d.mass.inertiaCm, friction(id).rotationalFriction);
    r.model = m.hinge ? Model::Cylindrical : Model::None;
    m.radius = collision.maxRadius(collision::ObjectId::part(id), c.partAxis);
    m.clearance = scene->support(ci).clearance;
    m.play.setZero();
    updatePlay(id);
    setPose(id, basePose * currentInBase(id));
  } else {
    m.hinge.reset();
    m.clearance = 0.0;
    m.play.setZero();
    r.model = Model::Plane;
    const dyn::PlaneSlideInput in = dyn::planeInWorld(c.basePlane.normal, Eigen::Isometry3d::Identity(), Eigen::Vector3d::Zero());
    m.nb = in.n;
    m.e1b = in.e1;
    m.e2b = in.e2;
  }
}

// Advances the on-base model of `id` by one step from its current coordinates; handles the events.
void World::Impl::stepOnBase(PartId id, const Eigen::Vector3d& leaving) {
  flush(id);
  PartRuntime& r = parts[id];
  PartModel& m = models[id];
  updatePlay(id);
  const dyn::Friction fr = slideFriction(id);
  const collision::Support& sup = scene->support(*r.constraint);
  const Eigen::Isometry3d B = basePose;
  double a0 = r.angle, s0 = r.slide, a1 = a0, s1 = s0, w1 = r.omega, sv1 = r.slideRate;
  Eigen::Vector2d p0 = r.planeP, p1 = p0, pv1 = r.planeV;
  dyn::SlideEvent slideEvent = dyn::SlideEvent::None;
  bool rotationAtRest = true;
  if (r.model == Model::Cylindrical) {
    const dyn::HingeTorque tq = m.hinge->torque(B.linear(), gravity(settings.gravity.rotation));
    dyn::HingeState hs{a0, r.omega};
    m.hinge->step(hs, tq, h(), settings.rotationMethod);
    a1 = hs.angle;
    w1 = hs.omega;
    dyn::AxisSlideState ss{s0, r.slideRate, m.sliding};
    dyn::AxisSlideInput in;
    in.u = B.linear() * m.hinge->axisInBase();
    in.g = gravity(settings.gravity.slide);
    slideEvent = dyn::stepAxisSlide(ss, in, fr, h(), dyn::Method::Exact).event;
    s1 = ss.s;
    sv1 = ss.v;
    m.sliding = ss.moving;
    const double tau = tq.A * std::cos(a1) + tq.B * std::sin(a1);
    rotationAtRest = std::abs(w1) < 1e-3 && std::abs(tau) <= torqueEps(id);
  } else {
    const dyn::PlaneSlideInput in = dyn::planeInWorld(m.nb, B, gravity(settings.gravity.slide));
    dyn::PlaneSlideState ps{p0, r.planeV, m.sliding};
    slideEvent = dyn::stepPlaneSlide(ps, in, fr, h(), dyn::Method::Exact).event;
    if (slideEvent == dyn::SlideEvent::LostContact) {
      leaveBase(id, Eigen::Vector3d::Zero(), "gravity pulls it off the surface");
      return;
    }
    p1 = ps.p;
    pv1 = ps.v;
    m.sliding = ps.moving;
  }
  // The two collision checks along the step's motion.
  const double travel = std::abs(s1 - s0) + std::abs(a1 - a0) * m.radius + (p1 - p0).norm();
  collision::MotionEvent ev;
  ev.kind = collision::EventKind::None;
  ev.s = 1.0;
  if (travel > 1e-12) {
    // Along the part of the step that stays inside the free motion found around an earlier pose nothing
    // can happen; only the rest is searched, starting where it leaves it (docs/collision.md, "Free motion").
    const std::uint64_t others = moves - ownMoves[id];
    if (!m.free.valid || m.free.others != others || !(m.free.base == B.matrix())) {
      m.free.motion = collision.freeMotion(sup, B * inBaseOf(id, a0, s0, p0));
      m.free.valid = true;
      m.free.others = others;
      m.free.base = B.matrix();
      m.free.slide = s0;
      m.free.planeP = p0;
    }
    const auto [inside, bound] = freeFraction(m.free, r.model, s0, s1, p0, p1);
    if (inside < 1.0) {
      collision::Motion motion;
      motion.s0 = inside;
      motion.s1 = 1.0;
      motion.speedBound = travel;
      motion.pose = [this, id, B, a0, a1, s0, s1, p0, p1](double x) {
        return B * inBaseOf(id, a0 + x * (a1 - a0), s0 + x * (s1 - s0), p0 + x * (p1 - p0));
      };
      collision::ToiOptions options;
      options.startFree = inside > 0.0;
      // Where an obstacle bounds the free motion, it ends half a tolerance inside it: a first sample one
      // tolerance farther is blocked by a face-on contact, and brackets the event to the tolerance without
      // bisection; the part is left where the free motion ends, half a tolerance inside the allowance, not
      // on it, where rounding would decide whether it is blocked where it rests. Where the touch ends it,
      // touch is lost within two tolerances.
      if (bound == Bound::Obstacle) options.firstStep = options.tolerance;
      if (bound == Bound::Touch) options.firstStep = 2.0 * options.tolerance;
      ev = collision::firstEventOnBase(collision, sup, motion, options);
      // A part stopped by an obstacle rests at that contact's allowance, where rounding decides whether its
      // start counts as blocked once the base has turned; moving away from what stopped it, that contact
      // cannot block it (a sleeve resting on its shaft's shoulder, the base turned over: it slides off).
      if (ev.kind == collision::EventKind::Blocked && ev.initiallyBlocked && !options.startFree) {
        const Eigen::Vector3d way = r.model == Model::Cylindrical ? Eigen::Vector3d(m.hinge->axisInBase() * (s1 - s0))
                                                                  : Eigen::Vector3d(m.e1b * (p1 - p0).x() + m.e2b * (p1 - p0).y());
        if (leaving.dot(way) < 0.0) {
          options.startFree = true;
          ev = collision::firstEventOnBase(collision, sup, motion, options);
        }
      }
      m.free.valid = false;  // found again around the next step's start
    }
  }
  if (r.model == Model::Cylindrical && s1 != s0) {
    // A mate across the axis is a stop along it: a peg in a blind hole of its own radius, a nut on what it
    // clamps. Decided on the exact planes, not the meshes, whose equal-radius rims only ever touch.
    if (const auto stop = mateStop(id, a0, s0, s1); stop && stop->first < (ev.kind == collision::EventKind::None ? 1.0 : ev.s)) {
      ev.kind = collision::EventKind::Blocked;
      ev.s = stop->first;
      ev.other = stop->second;
    }
  }
  const double x = ev.kind == collision::EventKind::None ? 1.0 : ev.s;
  r.angle = a0 + x * (a1 - a0);
  r.slide = s0 + x * (s1 - s0);
  r.planeP = p0 + x * (p1 - p0);
  r.omega = w1;
  r.slideRate = sv1;
  r.planeV = pv1;
  setPose(id, B * currentInBase(id));
  // World velocity of the CM and angular velocity (for a hand-over to free flight).
  Eigen::Vector3d v = Eigen::Vector3d::Zero(), w = Eigen::Vector3d::Zero();
  if (r.model == Model::Cylindrical) {
    const Eigen::Vector3d u = B.linear() * m.hinge->axisInBase();
    const Eigen::Vector3d arm = comWorld(id) - B * Eigen::Vector3d(inBaseFrame[*r.constraint].baseAxis.point + m.play);
    w = u * r.omega;
    v = u * r.slideRate + w.cross(arm - u * u.dot(arm));
  } else {
    const dyn::PlaneSlideInput in = dyn::planeInWorld(m.nb, B, Eigen::Vector3d::Zero());
    v = in.e1 * r.planeV.x() + in.e2 * r.planeV.y();
  }
  r.velocity = v;
  r.angularVelocity = w;
  if (ev.kind == collision::EventKind::Blocked) {
    Eigen::Vector3d dirBase = Eigen::Vector3d::Zero();
    if (r.model == Model::Cylindrical) {
      dirBase = m.hinge->axisInBase() * (s1 - s0);
    } else {
      dirBase = m.e1b * (p1 - p0).x() + m.e2b * (p1 - p0).y();
    }
    m.blockedDir = dirBase.norm() > 0.0 ? Eigen::Vector3d(dirBase.normalized()) : Eigen::Vector3d::Zero();
    m.blockedRot = (a1 - a0) > 0.0 ? 1.0 : ((a1 - a0) < 0.0 ? -1.0 : 0.0);
    r.omega = r.slideRate = 0.0;
    r.planeV.setZero();
    r.velocity.setZero();
    r.angularVelocity.setZero();
    m.sliding = false;
    fireEvent(id, Event::Blocked, interact::Hands::None,
              "blocked by " + objectName(ev.other) + fmt(" after %.6f of the step", x));
    placeIfHome(id);
    return;
  }
  if (ev.kind == collision::EventKind::LostTouch) {
    leaveBase(id, v, "lost touch: " + ev.touch.reason + fmt(" (margin %.6f m)", ev.touch.margin), w);
    return;
  }
  if (slideEvent == dyn::SlideEvent::Stopped && rotationAtRest) {
    r.omega = r.slideRate = 0.0;
    r.planeV.setZero();
    r.velocity.setZero();
    r.angularVelocity.setZero();
    fireEvent(id, Event::Stopped, interact::Hands::None, "kinetic friction stopped it");
    placeIfHome(id);
  } else if (r.model == Model::Cylindrical && !m.sliding && rotationAtRest) {
    r.omega = 0.0;
    r.velocity.setZero();
    r.angularVelocity.setZero();
    fireEvent(id, Event::Stopped, interact::Hands::None, "rotation came to rest");
    placeIfHome(id);
  }
}

std::optional<std::pair<double, collision::ObjectId>> World::Impl::mateStop(PartId id, double angle, double s0, double s1) const {
  const Eigen::Vector3d u = models[id].hinge->axisInBase();
  std::optional<std::pair<double, collision::ObjectId>> first;
  for (const Constraint& c : inBaseFrame) {
    if (c.part != id || c.type != Constraint::Type::Mate) continue;
    if (c.partner && parts[*c.partner].state != PartState::Placed) continue;
    if (std::abs(c.basePlane.normal.dot(u)) < std::cos(settings.recognizeAngle * kDeg)) continue;
    const auto gap = [&](double s) {
      return c.basePlane.normal.dot(inBaseOf(id, angle, s, Eigen::Vector2d::Zero()) * c.partPlane.point - c.basePlane.point) - c.offset;
    };
    const double g0 = gap(s0), g1 = gap(s1);
    // Only a motion into the partner's face from its free side (within the contact tolerance) is stopped.
    if (!(g1 < g0) || g0 < -collision.tolerances().distance || g1 >= 0.0) continue;
    const double x = std::clamp(std::max(g0, 0.0) / (g0 - g1), 0.0, 1.0);
    if (!first || x < first->first)
      first = std::pair{x, collision::ObjectId::part(c.partner.value_or(*base))};
  }
  return first;
}

void World::Impl::placeIfHome(PartId id) {
  if (!settings.placeAtRest || parts[id].state != PartState::OnBaseStatic) return;
  Eigen::Isometry3d snapped;
  if (!atFinalPose(id, snapped)) return;
  PartRuntime& r = parts[id];
  const Eigen::Isometry3d before = r.pose;
  if (!fireEvent(id, Event::ReachedFinalLocation, interact::Hands::None,
                 fmt("came to rest %.6f m, %.4f deg from the final pose", (snapped.translation() - before.translation()).norm(),
                     angleOf(snapped.linear().transpose() * before.linear()) / kDeg)))
    return;
  setPose(id, snapped);
  r.model = Model::None;
  models[id].inBase = basePose.inverse() * snapped;
  r.velocity.setZero();
  r.angularVelocity.setZero();
}

void World::Impl::leaveBase(PartId id, const Eigen::Vector3d& v, const std::string& cause, const Eigen::Vector3d& w) {
  if (fireEvent(id, Event::LostContact, interact::Hands::None, cause)) {
    enterFlight(id, v, w, endOfStep());
    models[id].clearing = true;
  }
}

// ONBASESTATIC: moves with the base; starts when gravity beats static friction (not into the obstacle
// that last blocked it).
void World::Impl::checkStart(PartId id) {
  PartRuntime& r = parts[id];
  PartModel& m = models[id];
  updatePlay(id);
  setPose(id, basePose * currentInBase(id));
  if (r.model == Model::None || !r.constraint) return;
  const dyn::Friction fr = slideFriction(id);
  bool starts = false;
  Eigen::Vector3d dirBase = Eigen::Vector3d::Zero();
  double rotSign = 0.0;
  Eigen::Vector3d normalWorld = Eigen::Vector3d::UnitZ();
  if (r.model == Model::Cylindrical) {
    const Eigen::Vector3d u = basePose.linear() * m.hinge->axisInBase();
    normalWorld = u;
    const dyn::HingeTorque tq = m.hinge->torque(basePose.linear(), gravity(settings.gravity.rotation));
    const double tau = tq.A * std::cos(r.angle) + tq.B * std::sin(r.angle);
    if (std::abs(tau) > torqueEps(id)) {
      starts = true;
      rotSign = tau > 0.0 ? 1.0 : -1.0;
    }
    const dyn::AxisGravity gr = dyn::splitGravity(u, gravity(settings.gravity.slide));
    if (std::abs(gr.along) > fr.fs * gr.normal) {
      starts = true;
      dirBase = m.hinge->axisInBase() * (gr.along > 0.0 ? 1.0 : -1.0);
    }
  } else {
    dyn::PlaneSlideInput in = dyn::planeInWorld(m.nb, basePose, gravity(settings.gravity.slide));
    normalWorld = in.n;
    dyn::PlaneSlideState ps{r.planeP, Eigen::Vector2d::Zero(), false};
    const dyn::SlideEvent e = dyn::stepPlaneSlide(ps, in, fr, h(), dyn::Method::Exact).event;
    if (e == dyn::SlideEvent::LostContact) {
      if (fireEvent(id, Event::StaticFrictionOvercome, interact::Hands::None, "gravity pulls it off the surface"))
        leaveBase(id, Eigen::Vector3d::Zero(), "gravity pulls it off the surface");
      return;
    }
    if (e == dyn::SlideEvent::Started) {
      starts = true;
      const Eigen::Vector2d d = ps.p - r.planeP;
      dirBase = m.e1b * d.x() + m.e2b * d.y();
    }
  }
  if (!starts) return;
  // Into the obstacle that blocked it last: stays (a rotation away from it, or a slide away, may go).
  const bool slideInto = dirBase.norm() > 0.0 && m.blockedDir.dot(dirBase.normalized()) > 1e-9;
  const bool rotInto = rotSign != 0.0 && rotSign == m.blockedRot;
  const bool slideFree = dirBase.norm() > 0.0 && !slideInto;
  const bool rotFree = rotSign != 0.0 && !rotInto;
  if (!slideFree && !rotFree) return;
  if (!fireEvent(id, Event::StaticFrictionOvercome, interact::Hands::None, tiltCause(normalWorld))) return;
  const Eigen::Vector3d leaving = slideFree ? m.blockedDir : Eigen::Vector3d::Zero();
  if (slideFree) m.blockedDir.setZero();
  if (rotFree) m.blockedRot = 0.0;
  stepOnBase(id, leaving);
}

}  // namespace vaw::sim

namespace vaw::sim {

std::optional<dyn::StabilityReport> World::rotationStability(PartId id) const {
  const Impl& w = *impl_;
  if (id >= w.parts.size() || !w.base) return std::nullopt;
  const PartRuntime& r = w.parts[id];
  const Part& d = w.def(id);
  std::optional<dyn::Hinge> hinge;
  if (r.model == Model::Cylindrical && w.models[id].hinge) {
    hinge = w.models[id].hinge;
  } else {
    const auto c = std::find_if(w.inBaseFrame.begin(), w.inBaseFrame.end(), [&](const Constraint& k) {
      return k.part == id && k.type == Constraint::Type::Insert;
    });
    if (c == w.inBaseFrame.end()) return std::nullopt;
    // Where it would turn: at its assembled pose relative to the base (the load pose without one).
    const Eigen::Isometry3d inBase = w.baseLoad.inverse() * d.finalPose.value_or(d.pose);
    hinge = dyn::Hinge::make(c->baseAxis.point, c->baseAxis.direction, inBase, d.mass.mass, d.mass.centerOfMass,
                             d.mass.inertiaCm, w.friction(id).rotationalFriction);
  }
  if (!hinge || hinge->inertia() <= 0.0) return std::nullopt;
  const dyn::HingeTorque tq = hinge->torque(w.basePose.linear(), w.gravity(w.settings.gravity.rotation));
  return dyn::checkStability(w.settings.rotationMethod, hinge->naturalFrequency(tq), hinge->friction() / hinge->inertia(),
                             w.h());
}

}  // namespace vaw::sim
