#include "vaw/collision/time_of_impact.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace vaw::collision {

Motion translation(const Eigen::Isometry3d& start, const Eigen::Vector3d& direction, double length) {
  const Eigen::Vector3d u = direction.normalized();
  Motion m;
  m.pose = [start, u](double s) {
    Eigen::Isometry3d p = start;
    p.pretranslate(s * u);
    return p;
  };
  m.s0 = 0.0;
  m.s1 = length;
  m.speedBound = 1.0;
  return m;
}

Motion axisSlide(const Eigen::Isometry3d& start, const Eigen::Vector3d& u, double v0, double a, double h) {
  const Eigen::Vector3d dir = u.normalized();
  Motion m;
  m.pose = [start, dir, v0, a](double t) {
    Eigen::Isometry3d p = start;
    p.pretranslate((v0 * t + 0.5 * a * t * t) * dir);
    return p;
  };
  m.s1 = h;
  m.speedBound = std::max(std::abs(v0), std::abs(v0 + a * h));  // |v| is linear in t: largest at an end
  return m;
}

Motion planeSlide(const Eigen::Isometry3d& start, const Eigen::Vector3d& e1, const Eigen::Vector3d& e2,
                  const Eigen::Vector2d& v0, const Eigen::Vector2d& a, double h) {
  Motion m;
  m.pose = [start, e1, e2, v0, a](double t) {
    const Eigen::Vector2d d = v0 * t + 0.5 * a * t * t;
    Eigen::Isometry3d p = start;
    p.pretranslate(d.x() * e1 + d.y() * e2);
    return p;
  };
  m.s1 = h;
  m.speedBound = std::max(v0.norm(), (v0 + a * h).norm());  // |v(t)| is convex in t
  return m;
}

Motion hingeRotation(const dyn::Hinge& hinge, const Eigen::Isometry3d& baseToWorld, double angle0, double angle1,
                     double radius) {
  const double sign = angle1 >= angle0 ? 1.0 : -1.0;
  Motion m;
  m.pose = [hinge, baseToWorld, angle0, sign](double s) { return Eigen::Isometry3d(baseToWorld * hinge.partInBase(angle0 + sign * s)); };
  m.s1 = std::abs(angle1 - angle0);
  m.speedBound = radius;  // m per rad
  return m;
}

Motion ballistic(const dyn::Release& release, const Eigen::Vector3d& gScaled, const Eigen::Vector3d& com, double t0,
                 double t1, double radius) {
  Motion m;
  m.pose = [release, gScaled, com](double t) {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.linear() = dyn::constantOmegaOrientation(release, t).toRotationMatrix();
    p.translation() = dyn::ballisticPosition(release, gScaled, t) - p.linear() * com;
    return p;
  };
  m.s0 = t0;
  m.s1 = t1;
  m.speedBound = std::max(dyn::ballisticVelocity(release, gScaled, t0).norm(), dyn::ballisticVelocity(release, gScaled, t1).norm()) +
                 release.omega.norm() * radius;
  return m;
}

MotionEvent timeOfImpact(const CollisionWorld& world, ObjectId mover, const Motion& motion, const ToiOptions& options) {
  MotionEvent ev;
  ev.s = ev.sEvent = motion.s1;
  const double tol = options.tolerance;
  const double L = motion.speedBound;
  const double span = std::max(0.0, motion.s1 - motion.s0);
  // Everything the part can reach during the motion (broad phase, once).
  Eigen::AlignedBox3d reach = world.worldBounds(mover, motion.pose(motion.s0));
  if (reach.isEmpty()) return ev;
  reach.min().array() -= L * span + tol;
  reach.max().array() += L * span + tol;
  const std::vector<ObjectId> candidates = world.near(reach, mover);
  double s = motion.s0;
  for (int it = 0; it < options.maxIterations; ++it) {
    const Eigen::Isometry3d pose = motion.pose(s);
    double d = std::numeric_limits<double>::infinity();
    std::optional<ObjectId> nearest;
    for (const ObjectId& c : candidates) {
      const double dc = world.distance(mover, pose, c);
      ++ev.evaluations;
      if (dc < d) {
        d = dc;
        nearest = c;
      }
    }
    if (d <= tol) {
      ev.kind = EventKind::Contact;
      ev.s = ev.sEvent = s;
      ev.other = nearest;
      ev.distance = d;
      ev.initiallyBlocked = s == motion.s0;
      return ev;
    }
    if (s >= motion.s1 || L <= 0.0) break;
    // No point moves faster than L, so nothing can be hit before the gap minus half the tolerance is closed.
    s = std::min(motion.s1, s + (d - 0.5 * tol) / L);
  }
  ev.s = ev.sEvent = motion.s1;
  return ev;
}

MotionEvent firstEventOnBase(const CollisionWorld& world, const Support& support, const Motion& motion,
                             const ToiOptions& options) {
  MotionEvent ev;
  ev.s = ev.sEvent = motion.s1;
  const double L = motion.speedBound;
  const double span = std::max(0.0, motion.s1 - motion.s0);
  // The last blocked check, kept: the event's contacts are those found where it was last seen blocked.
  double lastS = std::numeric_limits<double>::quiet_NaN();
  BlockResult last;
  auto isBlocked = [&](double s) {
    ++ev.evaluations;
    last = world.blocked(support, motion.pose(s), 1);
    lastS = s;
    return last.blocked;
  };
  auto isLost = [&](double s) {
    ++ev.evaluations;
    return !world.touching(support, motion.pose(s)).touching;
  };
  auto finish = [&](EventKind kind, double lo, double hi) {
    ev.kind = kind;
    ev.s = lo;
    ev.sEvent = hi;
    if (kind == EventKind::Blocked) {
      const BlockResult b = lastS == hi && last.blocked ? std::move(last) : world.blocked(support, motion.pose(hi), 8);
      ev.contacts = b.contacts;
      ev.other = b.by;
    }
    ev.touch = world.touching(support, motion.pose(hi));
    return ev;
  };
  if (!options.startFree) {
    const bool blocked0 = isBlocked(motion.s0), lost0 = isLost(motion.s0);
    if (blocked0 || lost0) {
      ev.initiallyBlocked = true;
      return finish(blocked0 ? EventKind::Blocked : EventKind::LostTouch, motion.s0, motion.s0);
    }
  }
  if (span <= 0.0 || L <= 0.0) return ev;
  auto bisect = [&](const auto& pred, double lo, double hi) {
    for (int it = 0; it < options.maxIterations && (hi - lo) * L > options.tolerance; ++it) {
      const double mid = 0.5 * (lo + hi);
      (pred(mid) ? hi : lo) = mid;
    }
    return std::pair{lo, hi};
  };
  // An expected event just beyond the start is bracketed by one short first sample (a few tolerances),
  // not by a whole maxStep that bisection must then narrow.
  double from = motion.s0;
  if (options.firstStep > 0.0 && options.firstStep < L * span) {
    from = motion.s0 + options.firstStep / L;
    const bool b = isBlocked(from), l = isLost(from);
    if (b || l) {
      std::pair<double, double> pb{from, from}, pl{from, from};
      if (b) pb = bisect(isBlocked, motion.s0, from);
      if (l) pl = bisect(isLost, motion.s0, from);
      if (b && (!l || pb.second <= pl.second)) return finish(EventKind::Blocked, pb.first, pb.second);
      return finish(EventKind::LostTouch, pl.first, pl.second);
    }
  }
  // Samples no farther apart than maxStep of motion of any point, then bisection to the tolerance.
  const double rest = motion.s1 - from;
  const int n = std::max(1, static_cast<int>(std::ceil(L * rest / options.maxStep)));
  double prev = from;
  for (int k = 1; k <= n; ++k) {
    const double s = k == n ? motion.s1 : from + rest * static_cast<double>(k) / static_cast<double>(n);
    const bool b = isBlocked(s), l = isLost(s);
    if (b || l) {
      std::pair<double, double> pb{s, s}, pl{s, s};
      if (b) pb = bisect(isBlocked, prev, s);
      if (l) pl = bisect(isLost, prev, s);
      if (b && (!l || pb.second <= pl.second)) return finish(EventKind::Blocked, pb.first, pb.second);
      return finish(EventKind::LostTouch, pl.first, pl.second);
    }
    prev = s;
  }
  return ev;
}

MotionEvent firstBlockBy(const CollisionWorld& world, ObjectId mover, ObjectId obstacle, const Motion& motion,
                         FilterMode mode, const ToiOptions& options) {
  MotionEvent ev;
  ev.s = ev.sEvent = motion.s1;
  const double L = motion.speedBound;
  QueryOptions q;
  q.mode = mode;
  q.maxContacts = 8;
  q.dropTouching = true;
  q.stopAtFirst = true;
  auto isBlocked = [&](double s) {
    ++ev.evaluations;
    return !world.query(mover, motion.pose(s), obstacle, q).contacts.empty();
  };
  auto finish = [&](double lo, double hi) {
    ev.kind = EventKind::Blocked;
    ev.s = lo;
    ev.sEvent = hi;
    ev.other = obstacle;
    QueryOptions all = q;
    all.stopAtFirst = false;
    ev.contacts = world.query(mover, motion.pose(hi), obstacle, all).contacts;
    return ev;
  };
  // Narrowed to the tolerance between a free lo and a blocked hi.
  auto bisect = [&](double lo, double hi) {
    for (int b = 0; b < options.maxIterations && (hi - lo) * L > options.tolerance; ++b) {
      const double mid = 0.5 * (lo + hi);
      (isBlocked(mid) ? hi : lo) = mid;
    }
    return finish(lo, hi);
  };
  const Eigen::Isometry3d start = motion.pose(motion.s0), end = motion.pose(motion.s1);
  const Eigen::Vector3d travel = end.translation() - start.translation();
  const bool straight = (end.linear() - start.linear()).norm() < 1e-12 && travel.norm() > 0.0;
  // Solids that share volume without their surfaces crossing (two equal shafts end to end) block where
  // their coaxial cylinders start to overlap: the sweep ends there unless something blocks it first.
  double until = motion.s1;
  if (straight && L > 0.0) until = std::min(until, motion.s0 + world.coaxialOverlapAlong(mover, start, obstacle, travel.normalized()) / L);
  if (until <= motion.s0 || isBlocked(motion.s0)) {
    ev.initiallyBlocked = true;
    return finish(motion.s0, motion.s0);
  }
  if (motion.s1 <= motion.s0 || L <= 0.0) return ev;
  double s = motion.s0;
  // A straight translation advances by the distance to what could still block it on the way (the contact
  // it slides along, and whatever it passes at a clearance, left out); any other motion by the distance.
  const auto gapAt = [&](double at) {
    // Beyond the rest of the way plus the tolerance a gap decides nothing more: the search stops there.
    return straight ? world.distanceAlong(mover, motion.pose(at), obstacle, mode, travel.normalized(),
                                          (until - at) * L + options.tolerance)
                    : world.distance(mover, motion.pose(at), obstacle);
  };
  // A distance query between parts in contact is the costliest check there is, and sliding parts stay in
  // contact: after each near one, the next few steps are sampled without asking, twice as many each time.
  int unasked = 0, skipNext = 1;
  for (int it = 0; it < options.maxIterations && s < until; ++it) {
    if (unasked > 0) {
      --unasked;
    } else {
      ++ev.evaluations;
      const double gap = gapAt(s);
      // No point moves faster than L: nothing meets before the gap less half the tolerance is closed.
      if (gap - 0.5 * options.tolerance >= options.maxStep) {
        s = std::min(until, s + (gap - 0.5 * options.tolerance) / L);
        skipNext = 1;
        continue;
      }
      // Touching: most such ways are blocked right there (a nut moved up into the plate it sits under, a
      // bolt's head come down onto the plate), which a check a few tolerances along brackets (a block is
      // a penetration beyond the tolerance and the facets' sagitta); otherwise bisection would narrow a
      // whole step. A contact it slides along pays one check each time its distance is asked.
      if (gap <= options.tolerance) {
        const double probe = std::min(until, s + 4.0 * options.tolerance / L);
        if (isBlocked(probe)) return bisect(s, probe);
      }
      unasked = skipNext;
      skipNext = std::min(2 * skipNext, 64);
    }
    const double next = std::min(until, s + options.maxStep / L);
    if (isBlocked(next)) return bisect(s, next);
    s = next;
  }
  if (s >= until && until < motion.s1) return finish(until, until);
  // Out of iterations before the end of the motion: not known to be free.
  ev.undecided = s < motion.s1;
  if (ev.undecided) ev.s = ev.sEvent = s;
  return ev;
}

}  // namespace vaw::collision
