// ODE (maximal coordinates, dWorldStep: the exact big-matrix LCP step, not the iterative QuickStep)
// running the slide and pendulum scenarios. Each run builds the world once, then the timed body resets
// the moving body and steps: world creation is not timed.
#include <ode/ode.h>

#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "engines.hpp"

namespace vaw::peers::detail {

namespace {

constexpr double kGravity = 9.80665;
constexpr int kMaxContacts = 4;
constexpr const char* kPrecision = sizeof(dReal) == sizeof(double) ? "double" : "single";

// ODE initialised once per process (dInitODE2 may not be nested), its per-thread data per calling thread.
void ensureOde() {
  struct Library {
    Library() {
      if (dInitODE2(0) == 0) throw std::runtime_error("ODE: dInitODE2 failed");
    }
    Library(const Library&) = delete;
    Library& operator=(const Library&) = delete;
    ~Library() { dCloseODE(); }
  };
  static const Library library;
  thread_local const bool threadReady = dAllocateODEDataForThread(dAllocateMaskAll) != 0;
  if (!threadReady) throw std::runtime_error("ODE: dAllocateODEDataForThread failed");
}

struct World {
  dWorldID world = nullptr;
  dSpaceID space = nullptr;
  dJointGroupID contacts = nullptr;
  World() {
    ensureOde();
    world = dWorldCreate();
    space = dSimpleSpaceCreate(nullptr);
    contacts = dJointGroupCreate(0);
    dWorldSetGravity(world, 0, 0, -kGravity);
  }
  World(const World&) = delete;
  World& operator=(const World&) = delete;
  ~World() {
    dJointGroupDestroy(contacts);
    dSpaceDestroy(space);  // destroys the geoms in it
    dWorldDestroy(world);  // destroys bodies and remaining joints
  }
};

void resetBody(dBodyID b, const dReal* pos, const dMatrix3 R, const dReal* v) {
  dBodySetPosition(b, pos[0], pos[1], pos[2]);
  dBodySetRotation(b, R);
  dBodySetLinearVel(b, v[0], v[1], v[2]);
  dBodySetAngularVel(b, 0, 0, 0);
  dBodySetForce(b, 0, 0, 0);
  dBodySetTorque(b, 0, 0, 0);
}

struct SlideContext {
  dWorldID world;
  dJointGroupID group;
  double mu;
};

void slideNearCallback(void* data, dGeomID a, dGeomID b) {
  const auto* ctx = static_cast<const SlideContext*>(data);
  std::array<dContact, kMaxContacts> c{};
  const int n = dCollide(a, b, kMaxContacts, &c[0].geom, static_cast<int>(sizeof(dContact)));
  for (int i = 0; i < n; ++i) {
    dContact& ci = c[static_cast<std::size_t>(i)];
    // Friction bounded by mu times the contact's normal force (friction pyramid, ODE's default
    // directions); no bounce; ERP and CFM from the world (0.2 and 1e-10 by default).
    ci.surface.mode = dContactApprox1;
    ci.surface.mu = ctx->mu;
    ci.surface.bounce = 0;
    const dJointID j = dJointCreateContact(ctx->world, ctx->group, &ci);
    dJointAttach(j, dGeomGetBody(a), dGeomGetBody(b));
  }
}

PeerResult slide(const vaw::dyn::SlideScenario& s, double stepRate, const vaw::dyn::WorkPrecisionOptions& o) {
  const int perSample = stepsPerSample(stepRate);
  const int n = sampleCount(s.duration);
  const double dt = 1.0 / stepRate;
  const double tilt = s.tiltDeg * std::numbers::pi / 180.0;
  const std::array<double, 3> normal{std::sin(tilt), 0.0, std::cos(tilt)};
  const std::array<double, 3> down{std::cos(tilt), 0.0, -std::sin(tilt)};

  World w;
  dCreatePlane(w.space, normal[0], normal[1], normal[2], 0);  // static: no body
  const dGeomID boxGeom = dCreateBox(w.space, s.size[0], s.size[1], s.size[2]);
  const dBodyID box = dBodyCreate(w.world);
  dMass m;
  dMassSetBoxTotal(&m, s.mass, s.size[0], s.size[1], s.size[2]);
  dBodySetMass(box, &m);
  dGeomSetBody(boxGeom, box);

  // Flat on the plane: body z along the normal, centre half the box height above the surface.
  dMatrix3 R;
  dRFromAxisAndAngle(R, 0, 1, 0, tilt);
  const double h = 0.5 * s.size[2];
  const std::array<dReal, 3> p0{normal[0] * h, normal[1] * h, normal[2] * h};
  const std::array<dReal, 3> v0{down[0] * s.v0, down[1] * s.v0, down[2] * s.v0};

  SlideContext ctx{w.world, w.contacts, s.fd};
  auto along = [&] {
    const dReal* p = dBodyGetPosition(box);
    return (p[0] - p0[0]) * down[0] + (p[1] - p0[1]) * down[1] + (p[2] - p0[2]) * down[2];
  };
  auto run = [&](vaw::dyn::Samples& out) {
    resetBody(box, p0.data(), R, v0.data());
    dJointGroupEmpty(w.contacts);
    out[0] = along();
    for (int i = 1; i < n; ++i) {
      for (int k = 0; k < perSample; ++k) {
        dSpaceCollide(w.space, &ctx, &slideNearCallback);
        dWorldStep(w.world, dt);
        dJointGroupEmpty(w.contacts);
      }
      out[static_cast<std::size_t>(i)] = along();
    }
  };

  std::string note = std::string("ODE dWorldStep (exact LCP, not QuickStep), ") + kPrecision + " precision: dCreateBox on dCreatePlane, "
                     "dSpaceCollide, up to " + std::to_string(kMaxContacts) +
                     " contact joints per step; one Coulomb coefficient mu = fd = " + fmt(s.fd) +
                     " with dContactApprox1 (friction pyramid, each direction bounded by mu x normal force; ODE's "
                     "default directions, across and along the slope here; no separate static coefficient fs = " +
                     fmt(s.fs) +
                     "); no bounce; world ERP " + fmt(static_cast<double>(dWorldGetERP(w.world))) + ", CFM " +
                     fmt(static_cast<double>(dWorldGetCFM(w.world))) +
                     " (defaults); auto-disable off; one step of 1/rate per frame; timed: collide + step (world built "
                     "once, box reset each run); coordinate: box centre displacement along the slope (m)";
  return measure(run, n, s.duration, o, std::move(note));
}

PeerResult pendulum(const vaw::dyn::PendulumScenario& p, double stepRate, const vaw::dyn::WorkPrecisionOptions& o) {
  const int perSample = stepsPerSample(stepRate);
  const int n = sampleCount(p.duration);
  const double dt = 1.0 / stepRate;
  const double theta0 = p.theta0Deg * std::numbers::pi / 180.0;
  constexpr double kThickness = 0.01;

  World w;
  const dBodyID disk = dBodyCreate(w.world);
  // Disk axis = body y = hinge axis (world y, horizontal). CM at the body origin.
  const double iTransverse = p.mass * (p.radius * p.radius / 4.0 + kThickness * kThickness / 12.0);
  dMass m;
  dMassSetParameters(&m, p.mass, 0, 0, 0, iTransverse, 0.5 * p.mass * p.radius * p.radius, iTransverse, 0, 0, 0);
  dBodySetMass(disk, &m);

  // Hinge through the world origin; at angle theta the CM is at R_y(theta) (0, 0, -arm).
  dMatrix3 R;
  dRFromAxisAndAngle(R, 0, 1, 0, theta0);
  const std::array<dReal, 3> cm0{-p.arm * std::sin(theta0), 0.0, -p.arm * std::cos(theta0)};
  const std::array<dReal, 3> zero{0, 0, 0};
  resetBody(disk, cm0.data(), R, zero.data());
  const dJointID hinge = dJointCreateHinge(w.world, nullptr);
  dJointAttach(hinge, disk, nullptr);
  dJointSetHingeAnchor(hinge, 0, 0, 0);
  dJointSetHingeAxis(hinge, 0, 1, 0);

  const double fr = p.fr;
  auto angle = [&] {
    const dReal* Rb = dBodyGetRotation(disk);  // 3x4, row major: body x axis in world = (Rb[0], Rb[4], Rb[8])
    return std::atan2(-Rb[8], Rb[0]);
  };
  auto run = [&](vaw::dyn::Samples& out) {
    resetBody(disk, cm0.data(), R, zero.data());
    out[0] = angle();
    for (int i = 1; i < n; ++i) {
      for (int k = 0; k < perSample; ++k) {
        // Viscous hinge friction (ODE's hinge has none): -fr * omega from the step's start.
        if (fr != 0) dBodyAddTorque(disk, 0, -fr * dBodyGetAngularVel(disk)[1], 0);
        dWorldStep(w.world, dt);
      }
      out[static_cast<std::size_t>(i)] = angle();
    }
  };

  std::string note = std::string("ODE dWorldStep (exact LCP, not QuickStep), ") + kPrecision + " precision: disk r = " + fmt(p.radius) +
                     " m, thickness " + fmt(kThickness) + " m, inertia set explicitly (J about the hinge = " +
                     fmt(p.inertia()) + " kg m^2); hinge joint to the world (maximal coordinates), world ERP " +
                     fmt(static_cast<double>(dWorldGetERP(w.world))) + ", CFM " +
                     fmt(static_cast<double>(dWorldGetCFM(w.world))) +
                     "; viscous friction applied as torque -fr*omega (fr = " + fmt(p.fr) +
                     ") before each step (dBodyAddTorque); one step of 1/rate per frame; no collision geometry; timed: "
                     "the stepping (world built once, disk reset each run); coordinate: angle from the bottom (rad)";
  return measure(run, n, p.duration, o, std::move(note));
}

}  // namespace

Peer odePeer() { return Peer{"ode", &slide, &pendulum}; }

}  // namespace vaw::peers::detail
