#pragma once
// Where along one step's motion a part first meets something (docs/collision.md, "Time of impact").
// A motion is the part's own reduced coordinate s mapped to a pose, with a bound on how fast any point of
// the part moves per unit of s. FCL's continuous collision is not used (in FCL 0.7 it misses
// obvious pass-throughs); instead:
// - free flight: conservative advancement on the distance to everything reachable (never steps past a
//   contact, so no tunnelling whatever the speed), stopping within `tolerance` of the first contact;
// - on the base: the blocked and touching checks sampled so that no point of the part moves more than
//   `maxStep` between samples, then bisection to `tolerance` inside the first failing interval.
#include <Eigen/Geometry>
#include <functional>
#include <optional>
#include <vector>

#include "vaw/collision/collision_world.hpp"
#include "vaw/dynamics/free_flight.hpp"
#include "vaw/dynamics/hinge.hpp"

namespace vaw::collision {

struct Motion {
  std::function<Eigen::Isometry3d(double s)> pose;  // part frame -> world at parameter s
  double s0 = 0.0, s1 = 0.0;
  double speedBound = 0.0;  // m per unit of s: no point of the part moves faster (must be > 0 to move)
};

// ---- the reduced models as motions ----
// Straight translation from `start` along unit `direction`; s in metres.
Motion translation(const Eigen::Isometry3d& start, const Eigen::Vector3d& direction, double length);
// 1-D slide within one step: displacement v0 t + a t^2 / 2 along unit u, s = t in [0, h] (s).
Motion axisSlide(const Eigen::Isometry3d& start, const Eigen::Vector3d& u, double v0, double a, double h);
// 2-D slide within one step on the plane spanned by unit e1, e2: p(t) = v0 t + a t^2 / 2, t in [0, h].
Motion planeSlide(const Eigen::Isometry3d& start, const Eigen::Vector3d& e1, const Eigen::Vector3d& e2,
                  const Eigen::Vector2d& v0, const Eigen::Vector2d& a, double h);
// Rotation about the hinge axis, s = angle (rad) from angle0 to angle1, with the base at baseToWorld;
// radius: largest distance of the part from the axis (CollisionWorld::maxRadius).
Motion hingeRotation(const dyn::Hinge& hinge, const Eigen::Isometry3d& baseToWorld, double angle0, double angle1,
                     double radius);
// Free flight from a release (CM position and orientation), constant-omega orientation; s = time t0..t1.
// com: centre of mass in the part frame; radius: largest distance of the part from its CM.
Motion ballistic(const dyn::Release& release, const Eigen::Vector3d& gScaled, const Eigen::Vector3d& com, double t0,
                 double t1, double radius);

struct ToiOptions {
  double tolerance = 1e-5;  // m: the reported contact lies within this distance (along the motion) of the true one
  double maxStep = 1e-3;    // m: on the base, no point moves more than this between two samples
  int maxIterations = 10000;
  // On the base: the motion's start is known free and touching (FreeMotion), so it is not checked again.
  bool startFree = false;
  // On the base: the first sample after the start this far along (m of motion of any point), when an
  // event is expected just beyond the start (an obstacle bounds a FreeMotion there); 0: maxStep.
  double firstStep = 0.0;
};

enum class EventKind { None, Blocked, LostTouch, Contact };

struct MotionEvent {
  EventKind kind = EventKind::None;
  // Last parameter known free (Blocked, Contact) or still touching (LostTouch): where to leave the part.
  // s1 when nothing happens.
  double s = 0.0;
  // First parameter at which the event holds; (sEvent - s) * speedBound <= tolerance.
  double sEvent = 0.0;
  std::optional<ObjectId> other;  // what blocked or was hit
  std::vector<Contact> contacts;  // at sEvent (Blocked): the blocking pairs found there, at least one
  TouchResult touch;              // at sEvent (LostTouch)
  double distance = 0.0;          // m, gap left at s (Contact)
  int evaluations = 0;            // checks or distance queries run
  bool initiallyBlocked = false;  // the event held already at s0
  // firstBlockBy: the iteration limit ran out at `s` before the motion's end, so nothing is known past it
  // (kind None; never to be read as free).
  bool undecided = false;
};

// Free flight: the first contact of `mover` with anything along the motion (NOCARE), by conservative
// advancement on the distance. The part is left at s with a gap in (tolerance/2, tolerance].
MotionEvent timeOfImpact(const CollisionWorld& world, ObjectId mover, const Motion& motion, const ToiOptions& options = {});

// On the base: the first of "blocked" and "lost touch" along the motion of the supported part.
MotionEvent firstEventOnBase(const CollisionWorld& world, const Support& support, const Motion& motion,
                             const ToiOptions& options = {});

// One pair: where along the motion `mover` is first blocked by `obstacle` (assembly evaluation: a part's way
// out of, or home into, an assembly). Pairs that only touch never block, and `mode` filters the pairs the
// motion slides along (SkipCoaxial for an insert's axis, SkipCoplanar for a face). Conservative advancement
// on the pair's distance while they are more than a maxStep apart, so a long way through free space costs a
// few distance queries; within a maxStep, the blocked check every maxStep of motion, then bisection to the
// tolerance (while they stay close, the distance is asked after 1, 2, 4 ... 64 such steps). Blocked at s0 (the two interfere where the motion starts): `initiallyBlocked`.
MotionEvent firstBlockBy(const CollisionWorld& world, ObjectId mover, ObjectId obstacle, const Motion& motion,
                         FilterMode mode, const ToiOptions& options = {});

}  // namespace vaw::collision
