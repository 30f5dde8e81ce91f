#include "vaw/sim/world.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numbers>
#include <utility>

#include "vaw/collision/collision_world.hpp"
#include "vaw/collision/time_of_impact.hpp"
#include "vaw/dynamics/free_flight.hpp"
#include "vaw/dynamics/hinge.hpp"
#include "vaw/dynamics/slide.hpp"

namespace vaw::sim {

using interact::Event;
using interact::PartState;

std::uint64_t fnv1a(const void* data, std::size_t size, std::uint64_t h) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) {
    h ^= p[i];
    h *= 0x100000001b3ULL;
  }
  return h;
}

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr std::size_t kMaxHistory = 64;

std::string fmt(const char* format, double a, double b = 0.0, double c = 0.0) {
  char buf[160];
  std::snprintf(buf, sizeof buf, format, a, b, c);
  return buf;
}

double angleOf(const Eigen::Matrix3d& r) { return Eigen::AngleAxisd(r).angle(); }

// Rotates `pose` about the world point `pivot` so that world direction `from` turns onto `to`.
Eigen::Isometry3d turnAbout(const Eigen::Isometry3d& pose, const Eigen::Vector3d& pivot, const Eigen::Vector3d& from,
                            const Eigen::Vector3d& to) {
  const Eigen::Matrix3d r = Eigen::Quaterniond::FromTwoVectors(from, to).toRotationMatrix();
  Eigen::Isometry3d out = pose;
  out.linear() = r * pose.linear();
  out.translation() = pivot + r * (pose.translation() - pivot);
  return out;
}

double exteriorDistance(const Eigen::AlignedBox3d& box, const Eigen::Vector3d& p) {
  return std::sqrt(box.squaredExteriorDistance(p));
}

}  // namespace

struct PartModel {
  std::vector<interact::PoseSample> history;
  Eigen::Isometry3d offset = Eigen::Isometry3d::Identity();  // holder frame -> part (hand, hoist)
  Eigen::Isometry3d inBase = Eigen::Isometry3d::Identity();  // part in base frame (PLACED, model reference)
  std::optional<dyn::Hinge> hinge;                           // cylindrical
  double clearance = 0.0;                                    // m, radial play of the fit (cylindrical)
  Eigen::Vector3d play = Eigen::Vector3d::Zero();            // base frame: where the play puts the part
  Eigen::Vector3d nb = Eigen::Vector3d::UnitZ(), e1b = Eigen::Vector3d::UnitX(), e2b = Eigen::Vector3d::UnitY();
  double radius = 0.0;                                       // largest distance from the axis (or CM)
  Eigen::Vector3d blockedDir = Eigen::Vector3d::Zero();     // base frame: the way it was last blocked
  double blockedRot = 0.0;                                   // sign of the rotation last blocked
  bool sliding = false;                                      // the slide's "moving" flag
  dyn::Release release;
  Eigen::Vector3d gFree = Eigen::Vector3d::Zero();
  dyn::RotationModel rotation = dyn::RotationModel::ConstantOmega;
  std::optional<dyn::TorqueFree> torqueFree;
  // The motions on the base that can meet nothing (collision::FreeMotion), found at `slide` / `planeP` and
  // valid while the base keeps the pose `base` and no other object moves (`others`, World::Impl::moves).
  struct Free {
    bool valid = false;
    std::uint64_t others = 0;
    Eigen::Matrix4d base = Eigen::Matrix4d::Identity();
    double slide = 0.0;
    Eigen::Vector2d planeP = Eigen::Vector2d::Zero();
    collision::FreeMotion motion;
  } free;
};

struct World::Impl {
  Assembly assembly;
  Settings settings;
  collision::CollisionWorld collision;
  std::vector<PartRuntime> parts;
  std::vector<PartModel> models;
  std::vector<std::optional<collision::Support>> supports;  // per constraint, made on first use
  std::vector<TransitionRecord> transitions;
  std::vector<Refusal> refusals;
  std::optional<PartId> base;
  Eigen::Isometry3d baseLoad = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d basePose = Eigen::Isometry3d::Identity();
  std::array<Eigen::Vector3d, 3> baseTrail{};  // the base's last three positions (inertial forces)
  int baseTrailCount = 0;
  Eigen::Vector3d baseAcceleration = Eigen::Vector3d::Zero();
  bool prevGrab[2] = {false, false};
  std::optional<PartId> held[2];
  bool prevHoist = false;
  std::optional<PartId> onHoist;
  std::uint64_t stepIndex = 0;
  double t = 0.0;
  std::size_t active = 0;
  // Pose changes, of all parts and per part: a part's free motion stays valid while every change since it
  // was found is its own.
  std::uint64_t moves = 0;
  std::vector<std::uint64_t> ownMoves;
  std::vector<char> dirty;        // per part: pose not yet given to the collision world
  std::vector<PartId> dirtyList;
  std::vector<PartId> awake;  // parts not STATIC (and not the base), in id order
  std::size_t awakeStamp = static_cast<std::size_t>(-1);  // transitions.size() when `awake` was made

  Impl(const Assembly& a, Settings s) : assembly(a), settings(s), collision(a) {
    base = assembly.base;
    if (base) baseLoad = basePose = assembly.parts[*base].pose;
    parts.resize(assembly.parts.size());
    models.resize(assembly.parts.size());
    supports.resize(assembly.constraints.size());
    dirty.assign(assembly.parts.size(), 0);
    ownMoves.assign(assembly.parts.size(), 0);
    for (std::size_t i = 0; i < parts.size(); ++i) {
      parts[i].id = i;
      parts[i].pose = assembly.parts[i].pose;
    }
  }

  [[nodiscard]] double h() const { return settings.step(); }
  [[nodiscard]] const Part& def(PartId id) const { return assembly.parts[id]; }
  [[nodiscard]] Material material(PartId id) const {
    const auto it = assembly.materials.find(def(id).material);
    return it == assembly.materials.end() ? Material{} : it->second;
  }
  [[nodiscard]] Eigen::Vector3d comWorld(PartId id) const { return parts[id].pose * def(id).mass.centerOfMass; }
  [[nodiscard]] std::string objectName(const std::optional<collision::ObjectId>& o) const {
    if (!o) return "?";
    if (o->kind == collision::ObjectId::Kind::Part) return assembly.parts[o->index].name;
    return assembly.environment[o->index].name;
  }

  // ---- transitions ----
  bool fireEvent(PartId id, Event e, interact::Hands hands, const std::string& cause) {
    interact::GuardContext ctx;
    ctx.category = def(id).category.category;
    ctx.hands = hands;
    PartRuntime& p = parts[id];
    const interact::Outcome o = interact::fire(p.state, e, ctx);
    if (!o.accepted) {
      refusals.push_back({stepIndex, endOfStep(), id, p.state, e, o.reason});
      return false;
    }
    transitions.push_back({stepIndex, endOfStep(), id, p.state, o.to, e, cause});
    p.state = o.to;
    return true;
  }

  const collision::Support& support(std::size_t c) {
    if (!supports[c]) supports[c] = collision.support(assembly.constraints[c]);
    return *supports[c];
  }

  // A moved part's pose reaches the collision world lazily: FCL's broad phase costs O(all objects) per
  // update (its tree height is recomputed), and a part's own queries pass its pose explicitly. So poses are
  // flushed only before a query by another part (or a grab, which reads bounds): with one active part the
  // step costs nothing per resting part.
  void setPose(PartId id, const Eigen::Isometry3d& pose) {
    if (!(pose.matrix() == parts[id].pose.matrix())) {
      ++moves;
      ++ownMoves[id];
    }
    parts[id].pose = pose;
    if (!dirty[id]) {
      dirty[id] = 1;
      dirtyList.push_back(id);
    }
  }
  void flush(std::optional<PartId> except = std::nullopt) {
    if (dirtyList.empty()) return;
    std::size_t kept = 0;
    for (const PartId d : dirtyList) {
      if (except && d == *except) {
        dirtyList[kept++] = d;
        continue;
      }
      collision.setPose(collision::ObjectId::part(d), parts[d].pose);
      dirty[d] = 0;
    }
    dirtyList.resize(kept);
  }

  // ---- the base ----
  void moveBase(const std::optional<Eigen::Isometry3d>& pose) {
    // A base held still costs nothing: the broad phase's update is O(all objects) in FCL 0.7.
    if (pose && base && !(pose->matrix() == basePose.matrix())) {
      ++moves;
      basePose = *pose;
      parts[*base].pose = basePose;
      collision.setPose(collision::ObjectId::part(*base), basePose);
    }
    // Acceleration of the base's origin from its last three positions (second difference).
    baseTrail[0] = baseTrail[1];
    baseTrail[1] = baseTrail[2];
    baseTrail[2] = basePose.translation();
    baseTrailCount = std::min(baseTrailCount + 1, 3);
    baseAcceleration = baseTrailCount == 3 ? Eigen::Vector3d((baseTrail[2] - 2.0 * baseTrail[1] + baseTrail[0]) / (h() * h()))
                                           : Eigen::Vector3d::Zero();
  }
  [[nodiscard]] Eigen::Vector3d gravity(double scale) const {
    return dyn::effectiveGravity(dyn::worldGravity() * scale, baseAcceleration, settings.inertialForces);
  }
  [[nodiscard]] std::string tiltCause(const Eigen::Vector3d& surfaceNormalWorld) const {
    const double tilt = angleOf(basePose.linear() * baseLoad.linear().transpose());
    const double slope = std::acos(std::clamp(surfaceNormalWorld.normalized().z(), -1.0, 1.0));
    return fmt("base tilt=%.4f deg, surface slope=%.4f deg", tilt / kDeg, slope / kDeg);
  }

  // ---- model coordinates -> pose ----
  [[nodiscard]] Eigen::Isometry3d inBaseOf(PartId id, double angle, double slide, const Eigen::Vector2d& p) const {
    const PartRuntime& r = parts[id];
    const PartModel& m = models[id];
    if (r.model == Model::Cylindrical && m.hinge) {
      Eigen::Isometry3d pose = m.hinge->partInBase(angle, slide);
      pose.pretranslate(m.play);
      return pose;
    }
    if (r.model == Model::Plane) {
      Eigen::Isometry3d shift = Eigen::Isometry3d::Identity();
      shift.translation() = m.e1b * p.x() + m.e2b * p.y();
      return shift * m.inBase;
    }
    return m.inBase;
  }
  // A bore with clearance rests on the side of its shaft that gravity pulls it to: its axis lies
  // `clearance` off the shaft's, along gravity's part across the axis (base frame). The slide's normal force
  // is that same part of gravity (dyn::splitGravity), so the friction is the contact's. With gravity
  // along the axis there is no such side, and the part stays where it was.
  void updatePlay(PartId id) {
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
  [[nodiscard]] Eigen::Isometry3d currentInBase(PartId id) const {
    const PartRuntime& r = parts[id];
    return inBaseOf(id, r.angle, r.slide, r.planeP);
  }

  // ---- recognition on release ----
  struct Recognition {
    std::size_t constraint = 0;
    Eigen::Isometry3d pose;
    double distance = 0.0, angle = 0.0;
  };
  std::optional<Recognition> recognize(PartId id) {
    if (!base) return std::nullopt;
    const Eigen::Isometry3d& P = parts[id].pose;
    const Eigen::Isometry3d& B = basePose;
    for (std::size_t ci = 0; ci < assembly.constraints.size(); ++ci) {
      const Constraint& c = assembly.constraints[ci];
      if (c.part != id) continue;
      Recognition rec;
      rec.constraint = ci;
      if (c.type == Constraint::Type::Insert) {
        const Eigen::Vector3d dp = P.linear() * c.partAxis.direction, pp = P * c.partAxis.point;
        const Eigen::Vector3d db = B.linear() * c.baseAxis.direction, pb = B * c.baseAxis.point;
        const double dot = dp.dot(db);
        rec.angle = std::acos(std::clamp(std::abs(dot), 0.0, 1.0));
        if (rec.angle > settings.recognizeAngle * kDeg) continue;
        const Eigen::Vector3d target = dot >= 0.0 ? db : Eigen::Vector3d(-db);
        rec.pose = turnAbout(P, pp, dp, target);
        const Eigen::Vector3d rel = pp - pb;
        const Eigen::Vector3d off = rel - db * db.dot(rel);
        rec.distance = off.norm();
        if (rec.distance > settings.recognizeDistance) continue;
        rec.pose.translation() -= off;
      } else {
        const Eigen::Vector3d np = P.linear() * c.partPlane.normal, pp = P * c.partPlane.point;
        const Eigen::Vector3d nb = B.linear() * c.basePlane.normal, pb = B * c.basePlane.point;
        const Eigen::Vector3d target = c.type == Constraint::Type::Mate ? Eigen::Vector3d(-nb) : nb;
        rec.angle = std::acos(std::clamp(np.dot(target), -1.0, 1.0));
        if (rec.angle > settings.recognizeAngle * kDeg) continue;
        rec.pose = turnAbout(P, pp, np, target);
        const double d = nb.dot(pp - pb) - c.offset;
        rec.distance = std::abs(d);
        if (rec.distance > settings.recognizeDistance) continue;
        rec.pose.translation() -= nb * d;
      }
      const collision::Support& s = support(ci);
      if (!s.problem.empty()) continue;
      if (!collision.touching(s, rec.pose).touching) continue;
      return rec;
    }
    return std::nullopt;
  }

  bool atFinalPose(PartId id, Eigen::Isometry3d& snapped) const {
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

  void enterOnBase(PartId id, std::size_t ci) {
    PartRuntime& r = parts[id];
    PartModel& m = models[id];
    const Constraint& c = assembly.constraints[ci];
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
                                 d.mass.inertiaCm, material(id).rotationalFriction);
      r.model = m.hinge ? Model::Cylindrical : Model::None;
      m.radius = collision.maxRadius(collision::ObjectId::part(id), c.partAxis);
      m.clearance = support(ci).clearance;
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

  // ---- free flight ----
  void enterFlight(PartId id, const Eigen::Vector3d& v, const Eigen::Vector3d& w, double t0) {
    PartRuntime& r = parts[id];
    PartModel& m = models[id];
    const Part& d = def(id);
    r.model = Model::Free;
    r.constraint.reset();
    r.velocity = v;
    r.angularVelocity = w;
    m.release = dyn::Release{t0, comWorld(id), v, Eigen::Quaterniond(r.pose.linear()), w};
    m.gFree = dyn::worldGravity() * settings.gravity.freeFlight;
    m.radius = collision.maxRadius(collision::ObjectId::part(id), d.mass.centerOfMass);
    // The flight time to the highest environment surface below the part.
    double zHit = -std::numeric_limits<double>::infinity();
    for (std::size_t e = 0; e < assembly.environment.size(); ++e) {
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

  void stepFlight(PartId id, double t0, double t1) {
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
    if (ev.kind == collision::EventKind::Contact) {
      setPose(id, motion.pose(ev.s));
      const Eigen::Vector3d vHit = dyn::ballisticVelocity(m.release, m.gFree, ev.s);
      r.velocity.setZero();
      r.angularVelocity.setZero();
      r.model = Model::None;
      fireEvent(id, Event::HitEnvironment, interact::Hands::None,
                "hit " + objectName(ev.other) + fmt(" at t=%.6f s, speed %.4f m/s", ev.s, vHit.norm()));
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
  // The fraction of a step's straight path (in the model's coordinates, from (s0, p0) to (s1, p1)) that stays
  // inside the free motion, from its start: 1 when all of it does, 0 when its start is outside; and what
  // bounds the free motion where the path leaves it.
  using Bound = collision::FreeMotion::Bound;
  [[nodiscard]] static std::pair<double, Bound> freeFraction(const PartModel::Free& f, Model model, double s0, double s1,
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

  [[nodiscard]] double torqueEps(PartId id) const {
    return 1e-6 * def(id).mass.mass * kStandardGravity * std::max(settings.gravity.rotation, 1e-12);
  }

  // Advances the on-base model of `id` by one step from its current coordinates; handles the events.
  void stepOnBase(PartId id) {
    flush(id);
    PartRuntime& r = parts[id];
    PartModel& m = models[id];
    updatePlay(id);
    const dyn::Friction fr{material(id).staticFriction, material(id).kineticFriction};
    const collision::Support& sup = support(*r.constraint);
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
        m.free.valid = false;  // found again around the next step's start
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
      const Eigen::Vector3d arm = comWorld(id) - B * Eigen::Vector3d(assembly.constraints[*r.constraint].baseAxis.point + m.play);
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
    } else if (r.model == Model::Cylindrical && !m.sliding && rotationAtRest) {
      r.omega = 0.0;
      r.velocity.setZero();
      r.angularVelocity.setZero();
      fireEvent(id, Event::Stopped, interact::Hands::None, "rotation came to rest");
    }
  }

  void leaveBase(PartId id, const Eigen::Vector3d& v, const std::string& cause,
                 const Eigen::Vector3d& w = Eigen::Vector3d::Zero()) {
    if (fireEvent(id, Event::LostContact, interact::Hands::None, cause)) enterFlight(id, v, w, endOfStep());
  }

  // ONBASESTATIC: moves with the base; starts when gravity beats static friction (not into the obstacle
  // that last blocked it).
  void checkStart(PartId id) {
    PartRuntime& r = parts[id];
    PartModel& m = models[id];
    updatePlay(id);
    setPose(id, basePose * currentInBase(id));
    if (r.model == Model::None || !r.constraint) return;
    const dyn::Friction fr{material(id).staticFriction, material(id).kineticFriction};
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
    if (slideFree) m.blockedDir.setZero();
    if (rotFree) m.blockedRot = 0.0;
    stepOnBase(id);
  }

  // ---- letting go (hand or hoist) ----
  void letGo(PartId id, bool tool, interact::Hands hands) {
    flush(id);
    PartRuntime& r = parts[id];
    PartModel& m = models[id];
    r.holder = Holder::None;
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
    const interact::Twist tw = interact::releaseVelocity(m.history, settings.release);
    const std::string cause = fmt("v=(%.4f, %.4f, %.4f) m/s", tw.linear.x(), tw.linear.y(), tw.linear.z());
    if (!fireEvent(id, Event::Release, hands, cause)) return;
    if (r.state == PartState::InSpace) {
      enterFlight(id, tw.linear, tw.angular, t);
      stepFlight(id, t, endOfStep());
    } else {
      r.model = Model::None;
      r.velocity.setZero();
    }
  }

  // ---- hands ----
  [[nodiscard]] bool grabbable(PartId id) const {
    if (base && id == *base) return false;
    const PartState s = parts[id].state;
    return s != PartState::InHand && s != PartState::OnTool;
  }
  [[nodiscard]] std::optional<PartId> nearest(const Eigen::Vector3d& at, double reach, bool forTool) const {
    std::optional<PartId> best;
    double bestD = std::numeric_limits<double>::infinity();
    for (PartId i = 0; i < parts.size(); ++i) {
      if (!grabbable(i)) continue;
      if (forTool && parts[i].state != PartState::Static && parts[i].state != PartState::OnBaseStatic &&
          parts[i].state != PartState::Placed)
        continue;
      if (exteriorDistance(collision.worldBounds(collision::ObjectId::part(i)), at) > reach) continue;
      const double d = (comWorld(i) - at).norm();
      if (d < bestD) {
        bestD = d;
        best = i;
      }
    }
    return best;
  }

  void hands(const Input& in) {
    const HandInput* hs[2] = {&in.left, &in.right};
    // Falling edges first: the part is let go where it was at the end of the last step.
    for (int k = 0; k < 2; ++k) {
      if (prevGrab[k] && !hs[k]->grab && held[k]) {
        const PartId id = *held[k];
        const Holder hd = parts[id].holder;
        held[0] = held[0] == id ? std::nullopt : held[0];
        held[1] = held[1] == id ? std::nullopt : held[1];
        letGo(id, false,
              hd == Holder::Both ? interact::Hands::Both : (k == 0 ? interact::Hands::Left : interact::Hands::Right));
      }
    }
    for (int k = 0; k < 2; ++k) {
      if (!hs[k]->grab || prevGrab[k] || held[k]) continue;
      flush();  // grabbing reads every part's world bounds
      const auto target = nearest(hs[k]->pose.translation(), settings.grabReach, false);
      if (!target) continue;
      const int o = 1 - k;
      const bool both = hs[o]->grab && !held[o] && nearest(hs[o]->pose.translation(), settings.grabReach, false) == target;
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

  [[nodiscard]] Eigen::Isometry3d hoistFrame(const HoistInput& hi) const {
    Eigen::Isometry3d f = Eigen::Isometry3d::Identity();
    f.linear() = Eigen::AngleAxisd(hi.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    f.translation() = Eigen::Vector3d(settings.hoistXY.x(), settings.hoistXY.y(), hi.height);
    return f;
  }

  void hoist(const HoistInput& hi) {
    if (prevHoist && !hi.engaged && onHoist) {
      const PartId id = *onHoist;
      onHoist.reset();
      letGo(id, true, interact::Hands::None);
    }
    if (hi.engaged && !prevHoist && !onHoist) {
      flush();
      const Eigen::Isometry3d f = hoistFrame(hi);
      if (const auto target = nearest(f.translation(), settings.hoistReach, true)) {
        if (fireEvent(*target, Event::ToolAttach, interact::Hands::None, fmt("hoist at z=%.4f m", hi.height))) {
          parts[*target].holder = Holder::Hoist;
          parts[*target].model = Model::Kinematic;
          parts[*target].constraint.reset();
          models[*target].offset = f.inverse() * parts[*target].pose;
          onHoist = target;
        }
      }
    }
    prevHoist = hi.engaged;
  }

  // Time from the step count, never a running sum: step n ends at exactly n / rate, however long the run.
  [[nodiscard]] double endOfStep() const { return static_cast<double>(stepIndex + 1) / settings.rate; }

  void step(const Input& in) {
    const double t1 = endOfStep();
    const bool baseMoved = in.base.has_value() && !in.base->isApprox(basePose, 0.0);
    moveBase(in.base);
    hands(in);
    hoist(in.hoist);
    active = 0;
    // Only parts that can move are visited: STATIC parts cost nothing per step. The list is rebuilt
    // (in id order, so the order of work never depends on history) after any transition.
    if (awakeStamp != transitions.size()) {
      awake.clear();
      for (PartId id = 0; id < parts.size(); ++id)
        if (!(base && id == *base) && parts[id].state != PartState::Static) awake.push_back(id);
      awakeStamp = transitions.size();
    }
    for (const PartId id : awake) {
      PartRuntime& r = parts[id];
      PartModel& m = models[id];
      switch (r.state) {
        case PartState::InHand: {
          ++active;
          const HandInput& hand = r.holder == Holder::Right ? in.right : in.left;
          setPose(id, hand.pose * m.offset);
          m.history.push_back({t1, comWorld(id), Eigen::Quaterniond(r.pose.linear())});
          if (m.history.size() > kMaxHistory) m.history.erase(m.history.begin());
          break;
        }
        case PartState::OnTool:
          ++active;
          setPose(id, hoistFrame(in.hoist) * m.offset);
          break;
        case PartState::InSpace:
          ++active;
          // Released this step: stepFlight already ran from the release.
          if (!transitions.empty() && transitions.back().part == id && transitions.back().step == stepIndex &&
              transitions.back().to == PartState::InSpace && transitions.back().event == Event::Release)
            break;
          stepFlight(id, t, t1);
          break;
        case PartState::OnBaseSlide:
          ++active;
          stepOnBase(id);
          break;
        case PartState::OnBaseStatic:
          // Only one-hand parts get dynamics (the table's guard): the others just ride on the base.
          if (def(id).category.category != Category::OneHand) {
            if (baseMoved) setPose(id, basePose * currentInBase(id));
            break;
          }
          ++active;
          checkStart(id);
          break;
        case PartState::Placed:
          if (baseMoved) setPose(id, basePose * m.inBase);
          break;
        case PartState::Static:
          break;
      }
    }
    if (base) parts[*base].pose = basePose;
    t = t1;
    ++stepIndex;
  }

  [[nodiscard]] std::uint64_t hash() const {
    std::uint64_t hv = fnv1a(&t, sizeof t);
    for (const PartRuntime& r : parts) {
      const auto st = static_cast<std::uint8_t>(r.state);
      hv = fnv1a(&st, 1, hv);
      hv = fnv1a(r.pose.matrix().data(), sizeof(double) * 16, hv);
      const double c[] = {r.angle, r.omega, r.slide, r.slideRate, r.planeP.x(), r.planeP.y(), r.planeV.x(),
                          r.planeV.y(), r.velocity.x(), r.velocity.y(), r.velocity.z(), r.angularVelocity.x(),
                          r.angularVelocity.y(), r.angularVelocity.z()};
      hv = fnv1a(c, sizeof c, hv);
    }
    return hv;
  }
};

World::World(const Assembly& assembly, Settings settings) : impl_(std::make_unique<Impl>(assembly, settings)) {}
World::~World() = default;
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;

void World::step(const Input& input) { impl_->step(input); }
double World::time() const { return impl_->t; }
std::uint64_t World::stepCount() const { return impl_->stepIndex; }
const Settings& World::settings() const { return impl_->settings; }
const Assembly& World::assembly() const { return impl_->assembly; }
const std::vector<PartRuntime>& World::parts() const { return impl_->parts; }
const PartRuntime& World::part(PartId id) const { return impl_->parts.at(id); }
Eigen::Isometry3d World::basePose() const { return impl_->basePose; }
const std::vector<TransitionRecord>& World::transitions() const { return impl_->transitions; }
const std::vector<Refusal>& World::refusals() const { return impl_->refusals; }
std::size_t World::activeParts() const { return impl_->active; }
std::uint64_t World::stateHash() const { return impl_->hash(); }

}  // namespace vaw::sim
