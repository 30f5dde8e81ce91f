#include "vaw/dynamics/slide.hpp"

#include <cmath>
#include <limits>

namespace vaw::dyn {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
double sign(double x) { return x > 0.0 ? 1.0 : (x < 0.0 ? -1.0 : 0.0); }

// Smallest t in (0, tMax] with s + v t + a t^2 / 2 = target, or infinity.
double firstCrossing(double s, double v, double a, double target, double tMax) {
  const double c = s - target;
  if (c == 0.0) return (v != 0.0 || a != 0.0) ? 0.0 : kInf;
  double best = kInf;
  auto consider = [&](double t) {
    if (t >= 0.0 && t <= tMax && t < best) best = t;
  };
  if (std::abs(a) < 1e-300) {
    if (v != 0.0) consider(-c / v);
    return best;
  }
  const double disc = v * v - 2.0 * a * c;
  if (disc < 0.0) return kInf;
  // Numerically stable roots of a/2 t^2 + v t + c = 0.
  const double q = -0.5 * (v + sign(v == 0.0 ? a : v) * std::sqrt(disc));
  if (q != 0.0) {
    consider(q / (0.5 * a));
    consider(c / q);
  }
  return best;
}

void noteEvent(SlideStep& r, SlideEvent e, double t) {
  r.event = e;
  r.eventTime = t;
}
}  // namespace

std::optional<Eigen::Vector3d> axisDirection(const Eigen::Vector3d& e1, const Eigen::Vector3d& e2, const Eigen::Vector3d& g) {
  const Eigen::Vector3d d = e2 - e1;
  const double n = d.norm();
  if (!(n > 1e-12)) return std::nullopt;
  Eigen::Vector3d u = d / n;
  if (u.dot(g) < 0.0) u = -u;
  return u;
}

std::optional<Eigen::Vector3d> lineOfPlanes(const Eigen::Vector3d& n1, const Eigen::Vector3d& n2, const Eigen::Vector3d& g) {
  const Eigen::Vector3d d = n1.cross(n2);
  const double n = d.norm();
  if (!(n > 1e-9 * n1.norm() * n2.norm())) return std::nullopt;
  Eigen::Vector3d u = d / n;
  if (u.dot(g) < 0.0) u = -u;
  return u;
}

double staticFrictionAngle(double fs) { return M_PI / 2.0 - std::atan(fs); }

AxisSlideInput axisInWorld(const Eigen::Vector3d& directionInBase, const Eigen::Isometry3d& basePose, const Eigen::Vector3d& g) {
  AxisSlideInput in;
  in.u = (basePose.linear() * directionInBase).normalized();
  in.g = g;
  return in;
}

PlaneSlideInput planeInWorld(const Eigen::Vector3d& normalInBase, const Eigen::Isometry3d& basePose, const Eigen::Vector3d& g) {
  const Eigen::Vector3d n = normalInBase.normalized();
  // Any base-fixed basis will do; take the base axis least aligned with the normal.
  Eigen::Index least = 0;
  n.cwiseAbs().minCoeff(&least);
  const Eigen::Vector3d e1 = (Eigen::Vector3d::Unit(least) - n * n[least]).normalized();
  const Eigen::Vector3d e2 = n.cross(e1);
  const Eigen::Matrix3d R = basePose.linear();
  PlaneSlideInput in;
  in.n = R * n;
  in.e1 = R * e1;
  in.e2 = R * e2;
  in.g = g;
  return in;
}

AxisGravity splitGravity(const Eigen::Vector3d& u, const Eigen::Vector3d& g) {
  const double along = g.dot(u);
  return {along, (g - u * along).norm()};
}

SlideStep stepAxisSlide(AxisSlideState& st, const AxisSlideInput& in, const Friction& f, double h, Method m) {
  const AxisGravity gr = splitGravity(in.u, in.g);
  SlideStep result;
  double elapsed = 0.0;
  // At most: start, stop, start again (thrown up a slope, stops, slides back), bound.
  for (int segment = 0; segment < 4 && elapsed < h; ++segment) {
    const double remaining = h - elapsed;
    if (!st.moving) {
      // Strictly greater: at exactly the friction angle the part stays (and never creeps by round-off).
      if (std::abs(gr.along) > f.fs * gr.normal) {
        st.moving = true;
        st.v = 0.0;
        noteEvent(result, SlideEvent::Started, elapsed);
      } else {
        return result;
      }
    }
    const double dir = st.v != 0.0 ? sign(st.v) : sign(gr.along);
    const double a = gr.along - f.fd * gr.normal * dir;
    const double tStop = (st.v != 0.0 && a * st.v < 0.0) ? -st.v / a : kInf;
    const double te = std::min(remaining, tStop);
    const auto accel = [a](double, double, double) { return a; };
    Phase next = step(m, accel, 0.0, Phase{st.s, st.v}, te);
    const double tLower = next.x < in.lower ? firstCrossing(st.s, st.v, a, in.lower, te) : kInf;
    const double tUpper = next.x > in.upper ? firstCrossing(st.s, st.v, a, in.upper, te) : kInf;
    if (tLower < kInf || tUpper < kInf) {
      const bool lower = tLower <= tUpper;
      const double tb = lower ? tLower : tUpper;
      next = step(m, accel, 0.0, Phase{st.s, st.v}, tb);
      st.s = lower ? in.lower : in.upper;
      st.v = next.v;
      noteEvent(result, lower ? SlideEvent::ReachedLower : SlideEvent::ReachedUpper, elapsed + tb);
      return result;
    }
    st.s = next.x;
    if (te == tStop) {
      st.v = 0.0;
      st.moving = false;
      noteEvent(result, SlideEvent::Stopped, elapsed + tStop);
    } else {
      st.v = next.v;
    }
    elapsed += te;
  }
  return result;
}

SlideStep stepPlaneSlide(PlaneSlideState& st, const PlaneSlideInput& in, const Friction& f, double h, Method m) {
  SlideStep result;
  const double pressing = -in.n.dot(in.g);  // |G_n| while gravity presses the part onto the surface
  if (!(pressing > 0.0)) {
    noteEvent(result, SlideEvent::LostContact, 0.0);
    return result;
  }
  const Eigen::Vector3d gt3 = in.g + in.n * pressing;
  const Eigen::Vector2d gt(gt3.dot(in.e1), gt3.dot(in.e2));
  double elapsed = 0.0;
  for (int segment = 0; segment < 3 && elapsed < h; ++segment) {
    const double remaining = h - elapsed;
    if (!st.moving) {
      if (gt.norm() > f.fs * pressing) {
        st.moving = true;
        st.v.setZero();
        noteEvent(result, SlideEvent::Started, elapsed);
      } else {
        return result;
      }
    }
    const double speed = st.v.norm();
    const Eigen::Vector2d dir = speed > 0.0 ? Eigen::Vector2d(st.v / speed) : Eigen::Vector2d(gt.normalized());
    const bool collinear = speed == 0.0 || std::abs(dir.x() * gt.y() - dir.y() * gt.x()) <= 1e-12 * gt.norm();
    // Rate of change of the speed; the stop inside the step is where it brings the speed to zero
    // (exact when collinear, first order otherwise).
    const double speedRate = dir.dot(gt) - f.fd * pressing;
    const double tStop = (speed > 0.0 && speedRate < 0.0) ? speed / -speedRate : kInf;
    const double te = std::min(remaining, tStop);
    PhaseOf<Eigen::Vector2d> next;
    if (collinear) {
      const Eigen::Vector2d a = dir * speedRate;  // along the line of motion only
      const auto accel = [&a](double, const Eigen::Vector2d&, const Eigen::Vector2d&) { return a; };
      next = step(m == Method::Exact ? Method::Exact : m, accel, 0.0, PhaseOf<Eigen::Vector2d>{st.p, st.v}, te);
    } else {
      const double fk = f.fd * pressing;
      const auto accel = [&gt, fk](double, const Eigen::Vector2d&, const Eigen::Vector2d& v) {
        const double s = v.norm();
        return Eigen::Vector2d(s > 0.0 ? Eigen::Vector2d(gt - fk * v / s) : gt);
      };
      next = step(m, accel, 0.0, PhaseOf<Eigen::Vector2d>{st.p, st.v}, te);
    }
    st.p = next.x;
    if (te == tStop) {
      st.v.setZero();
      st.moving = false;
      noteEvent(result, SlideEvent::Stopped, elapsed + tStop);
    } else {
      st.v = next.v;
    }
    elapsed += te;
  }
  return result;
}

}  // namespace vaw::dyn
