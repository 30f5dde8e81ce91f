// Bullet (maximal coordinates, sequential-impulse solver) running the slide and pendulum scenarios.
// Each run builds the world once, then the timed body resets the moving body and steps: world creation
// is not timed.
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "engines.hpp"

namespace vaw::peers::detail {

namespace {

constexpr double kGravity = 9.80665;
constexpr bool kDouble = sizeof(btScalar) == sizeof(double);

btScalar bs(double x) { return static_cast<btScalar>(x); }
btVector3 bv(double x, double y, double z) { return {bs(x), bs(y), bs(z)}; }

// One world with Bullet's default configuration. Bodies and constraints are plain locals declared after
// it, so they are destroyed first: a Leave guard declared after them takes them out of the world while
// they still exist (found by AddressSanitizer: the world's destructor read bodies already gone).
struct World {
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher{&config};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &config};

  World() { world.setGravity(bv(0.0, 0.0, -kGravity)); }
  World(const World&) = delete;
  World& operator=(const World&) = delete;
  ~World() = default;

  void removeAll() {
    for (int i = world.getNumConstraints() - 1; i >= 0; --i) world.removeConstraint(world.getConstraint(i));
    for (int i = world.getNumCollisionObjects() - 1; i >= 0; --i) {
      btCollisionObject* o = world.getCollisionObjectArray()[i];
      if (btRigidBody* b = btRigidBody::upcast(o)) world.removeRigidBody(b);
      else world.removeCollisionObject(o);
    }
  }
  struct Leave {
    World& w;
    explicit Leave(World& world) : w(world) {}
    Leave(const Leave&) = delete;
    Leave& operator=(const Leave&) = delete;
    ~Leave() { w.removeAll(); }
  };

  // One engine step of exactly dt: maxSubSteps = 0 makes Bullet take the given time step as is
  // (no fixed-step accumulator, no interpolation).
  void step(btScalar dt) { world.stepSimulation(dt, 0); }

  // Puts a body back to a pose and velocity, dropping its contact manifolds (and with them the
  // warm-start impulses) so that a repeat run starts like a fresh world.
  void reset(btRigidBody& b, const btTransform& pose, const btVector3& v, const btVector3& w) {
    b.setCenterOfMassTransform(pose);  // also the interpolation pose and the world inverse inertia
    b.setLinearVelocity(v);
    b.setAngularVelocity(w);
    b.setInterpolationLinearVelocity(v);
    b.setInterpolationAngularVelocity(w);
    b.clearForces();
    b.setDeactivationTime(0);
    if (b.getBroadphaseHandle() != nullptr)
      world.getBroadphase()->getOverlappingPairCache()->cleanProxyFromPairs(b.getBroadphaseHandle(), &dispatcher);
    world.updateSingleAabb(&b);
    solver.reset();
  }
};

std::string version() {
  return "Bullet " + std::to_string(BT_BULLET_VERSION / 100) + "." + std::to_string(BT_BULLET_VERSION % 100) +
         (kDouble ? " (double" : " (single") + " precision)";
}

PeerResult slide(const vaw::dyn::SlideScenario& s, double stepRate, const vaw::dyn::WorkPrecisionOptions& o) {
  const int perSample = stepsPerSample(stepRate);
  const int n = sampleCount(s.duration);
  const btScalar dt = bs(1.0 / stepRate);
  const double tilt = s.tiltDeg * std::numbers::pi / 180.0;
  // The incline: the plane z = 0 turned by `tilt` about +y. Normal and downhill direction (x-z plane).
  const btVector3 normal = bv(std::sin(tilt), 0.0, std::cos(tilt));
  const btVector3 down = bv(std::cos(tilt), 0.0, -std::sin(tilt));

  World w;
  // The incline is a large static box whose top face is the plane through the origin. Bullet's
  // btStaticPlaneShape was tried first: its convex-plane algorithm adds one contact point per step,
  // so the box rocks on an edge (and at 90 Hz sinks ~1 cm, at 30 Hz ~15 cm, and tumbles); the box-box
  // algorithm gives a full contact manifold.
  // Long enough for the frictionless travel in the scenario's duration, either way along the slope.
  const double reach =
      1.0 + std::abs(s.v0) * s.duration + 0.5 * kGravity * std::abs(std::sin(tilt)) * s.duration * s.duration;
  const double inclineHalf[3] = {std::max(5.0, reach), 5.0, 0.5};
  btBoxShape inclineShape(bv(inclineHalf[0], inclineHalf[1], inclineHalf[2]));
  const btQuaternion tilted(bv(0.0, 1.0, 0.0), bs(tilt));
  btRigidBody incline(btRigidBody::btRigidBodyConstructionInfo(0, nullptr, &inclineShape));
  incline.setWorldTransform(btTransform(tilted, normal * bs(-inclineHalf[2])));
  // Bullet combines friction (and restitution) as the product of the two bodies' values.
  incline.setFriction(1);
  incline.setRestitution(0);
  incline.setRollingFriction(0);

  btBoxShape boxShape(bv(0.5 * s.size[0], 0.5 * s.size[1], 0.5 * s.size[2]));  // default (safe) margin
  btVector3 inertia(0, 0, 0);
  boxShape.calculateLocalInertia(bs(s.mass), inertia);
  btRigidBody box(btRigidBody::btRigidBodyConstructionInfo(bs(s.mass), nullptr, &boxShape, inertia));
  box.setFriction(bs(s.fd));
  box.setRestitution(0);
  box.setRollingFriction(0);
  box.setActivationState(DISABLE_DEACTIVATION);
  w.world.addRigidBody(&incline);
  w.world.addRigidBody(&box);
  const World::Leave leave{w};

  // Flat on the plane: body z along the normal, centre half the box height above the surface.
  const btTransform start(tilted, normal * bs(0.5 * s.size[2]));
  const btVector3 v0 = down * bs(s.v0);

  auto run = [&](vaw::dyn::Samples& out) {
    w.reset(box, start, v0, btVector3(0, 0, 0));
    const btVector3 p0 = start.getOrigin();
    out[0] = static_cast<double>((box.getWorldTransform().getOrigin() - p0).dot(down));
    for (int i = 1; i < n; ++i) {
      for (int k = 0; k < perSample; ++k) w.step(dt);
      out[static_cast<std::size_t>(i)] = static_cast<double>((box.getWorldTransform().getOrigin() - p0).dot(down));
    }
  };

  std::string note = version() + ": btBoxShape (margin " + fmt(static_cast<double>(boxShape.getMargin())) +
                     " m, Bullet's safe default) on a static btBoxShape incline (" + fmt(2 * inclineHalf[0]) + " x " +
                     fmt(2 * inclineHalf[1]) + " x " + fmt(2 * inclineHalf[2]) +
                     " m; box-box manifold, not btStaticPlaneShape); one Coulomb coefficient mu = fd = " +
                     fmt(s.fd) + " (box fd x incline 1; Bullet has no separate static coefficient fs = " +
                     fmt(s.fs) + "); restitution 0; sequential impulse, " +
                     std::to_string(w.world.getSolverInfo().m_numIterations) +
                     " iterations, split impulse, one step of 1/rate per frame (stepSimulation(dt, 0)); "
                     "deactivation off; timed: the stepping (world built once, box reset each run); coordinate: box "
                     "centre displacement along the slope (m)";
  return measure(run, n, s.duration, o, std::move(note));
}

PeerResult pendulum(const vaw::dyn::PendulumScenario& p, double stepRate, const vaw::dyn::WorkPrecisionOptions& o) {
  const int perSample = stepsPerSample(stepRate);
  const int n = sampleCount(p.duration);
  const btScalar dt = bs(1.0 / stepRate);
  const double theta0 = p.theta0Deg * std::numbers::pi / 180.0;
  constexpr double kThickness = 0.01;

  World w;
  // The disk's symmetry axis is body y, which is also the hinge axis (world y, horizontal).
  btCylinderShape diskShape(bv(p.radius, 0.5 * kThickness, p.radius));
  const double iTransverse = p.mass * (p.radius * p.radius / 4.0 + kThickness * kThickness / 12.0);
  // About the hinge: 0.5 m r^2 + m arm^2 = PendulumScenario::inertia() (parallel axis, done by the joint).
  const btVector3 inertia = bv(iTransverse, 0.5 * p.mass * p.radius * p.radius, iTransverse);
  btRigidBody disk(btRigidBody::btRigidBodyConstructionInfo(bs(p.mass), nullptr, &diskShape, inertia));
  disk.setActivationState(DISABLE_DEACTIVATION);
  w.world.addRigidBody(&disk);

  // Hinge through the world origin; at angle theta the CM is at R_y(theta) (0, 0, -arm), so the pivot
  // sits at (0, 0, arm) in the body frame whatever the start angle.
  const btVector3 axis(0, 1, 0);
  const btQuaternion q0(axis, bs(theta0));
  const btTransform start(q0, quatRotate(q0, bv(0.0, 0.0, -p.arm)));
  w.reset(disk, start, btVector3(0, 0, 0), btVector3(0, 0, 0));
  // The constructor takes the hinge's world frame from the body's current pose, so the pose comes first.
  btHingeConstraint hinge(disk, bv(0.0, 0.0, p.arm), axis);
  w.world.addConstraint(&hinge, true);
  const World::Leave leave{w};

  const btScalar fr = bs(p.fr);
  auto run = [&](vaw::dyn::Samples& out) {
    w.reset(disk, start, btVector3(0, 0, 0), btVector3(0, 0, 0));
    auto angle = [&] {
      const btMatrix3x3& R = disk.getWorldTransform().getBasis();
      return std::atan2(-static_cast<double>(R[2][0]), static_cast<double>(R[0][0]));
    };
    out[0] = angle();
    for (int i = 1; i < n; ++i) {
      for (int k = 0; k < perSample; ++k) {
        // Viscous hinge friction, which Bullet lacks: -fr * omega from the step's start.
        if (fr != 0) disk.applyTorque(axis * (-fr * disk.getAngularVelocity().dot(axis)));
        w.step(dt);
      }
      out[static_cast<std::size_t>(i)] = angle();
    }
  };

  std::string note = version() + ": disk r = " + fmt(p.radius) + " m, thickness " + fmt(kThickness) +
                     " m, inertia set explicitly (J about the hinge = " + fmt(p.inertia()) +
                     " kg m^2); btHingeConstraint to the world (maximal coordinates), sequential impulse, " +
                     std::to_string(w.world.getSolverInfo().m_numIterations) +
                     " iterations, ERP 0.2; viscous friction applied as torque -fr*omega (fr = " + fmt(p.fr) +
                     ") before each step; one step of 1/rate per frame (stepSimulation(dt, 0)); "
                     "deactivation off; no other bodies, so no contacts; timed: the stepping (world built once, disk "
                     "reset each run); coordinate: angle from the bottom (rad)";
  return measure(run, n, p.duration, o, std::move(note));
}

}  // namespace

Peer bulletPeer() { return Peer{"bullet", &slide, &pendulum}; }

}  // namespace vaw::peers::detail
