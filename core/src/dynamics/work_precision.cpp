#include "vaw/dynamics/work_precision.hpp"

#include <time.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "vaw/dynamics/free_flight.hpp"
#include "vaw/dynamics/gravity.hpp"
#include "vaw/dynamics/hinge.hpp"
#include "vaw/dynamics/reference.hpp"
#include "vaw/dynamics/slide.hpp"
#include "vaw/dynamics/stability.hpp"
#include "vaw/units.hpp"

namespace vaw::dyn {

namespace {

using vaw::kDeg;
// Keeps the per-frame closed-form evaluations of the timed loop from being optimized away.
volatile double gSink = 0.0;

double cpuNow() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

int sampleCount(double duration) { return static_cast<int>(std::lround(duration / kSampleInterval)) + 1; }
int stepsPerSample(int rate) { return static_cast<int>(std::lround(rate * kSampleInterval)); }

AxisSlideInput slideInput(const SlideScenario& s) {
  AxisSlideInput in;
  in.u = Eigen::Vector3d(std::cos(s.tiltDeg * kDeg), 0.0, -std::sin(s.tiltDeg * kDeg));
  in.g = worldGravity();
  return in;
}

Samples runSlide(const SlideScenario& sc, Method m, int rate) {
  const AxisSlideInput in = slideInput(sc);
  const Friction f{sc.fs, sc.fd};
  AxisSlideState st{0.0, sc.v0, true};
  const int n = sampleCount(sc.duration), per = stepsPerSample(rate);
  const double h = 1.0 / rate;
  Samples out(static_cast<std::size_t>(n));
  out[0] = st.s;
  for (int k = 1; k < n; ++k) {
    for (int i = 0; i < per; ++i) stepAxisSlide(st, in, f, h, m);
    out[static_cast<std::size_t>(k)] = st.s;
  }
  return out;
}

Hinge makeHinge(const PendulumScenario& p) {
  const double r2 = p.radius * p.radius;
  const Eigen::Matrix3d I = Eigen::Vector3d(0.5 * p.mass * r2, 0.25 * p.mass * r2, 0.25 * p.mass * r2).asDiagonal();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(p.theta0Deg * kDeg, Eigen::Vector3d::UnitX()).toRotationMatrix();
  return *Hinge::make(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), pose, p.mass, Eigen::Vector3d(0, 0, -p.arm), I, p.fr);
}

Samples runPendulum(const PendulumScenario& p, const Hinge& hinge, Method m, int rate) {
  const HingeTorque tq = hinge.torque(Eigen::Matrix3d::Identity(), worldGravity());
  HingeState st;
  const int n = sampleCount(p.duration), per = stepsPerSample(rate);
  const double h = 1.0 / rate, theta0 = p.theta0Deg * kDeg;
  Samples out(static_cast<std::size_t>(n));
  out[0] = theta0;
  for (int k = 1; k < n; ++k) {
    for (int i = 0; i < per; ++i) hinge.step(st, tq, h, m);
    // A diverging method may overflow; keep the record finite so the chart can show it.
    out[static_cast<std::size_t>(k)] = std::isfinite(st.angle) ? theta0 + st.angle : 1e300;
  }
  return out;
}

Eigen::Matrix3d tumbleInertia(const TumbleScenario& t) {
  const double a = t.size[0], b = t.size[1], c = t.size[2];
  const double m = t.density * a * b * c;
  return (m / 12.0 * Eigen::Vector3d(b * b + c * c, a * a + c * c, a * a + b * b)).asDiagonal();
}

Release tumbleRelease(const TumbleScenario& t) {
  Release r;
  r.omega = Eigen::Vector3d(t.omega[0], t.omega[1], t.omega[2]);
  return r;
}

// The usual general-purpose answer, for comparison on the chart: classic RK4 on Euler's equations
// I w' = (I w) x w together with the quaternion kinematics q' = q (0, w) / 2, renormalized each step.
class EulerRk4 {
 public:
  EulerRk4(const Release& r, const Eigen::Matrix3d& inertia)
      : I_(inertia), Iinv_(inertia.inverse()), q_(r.orientation.normalized()), w_(q_.conjugate() * r.omega) {}
  void step(double h) {
    using V7 = Eigen::Matrix<double, 7, 1>;
    const auto f = [this](const V7& y) {
      const Eigen::Vector3d w = y.tail<3>();
      const Eigen::Quaterniond dq = Eigen::Quaterniond(y[0], y[1], y[2], y[3]) * Eigen::Quaterniond(0.0, w.x(), w.y(), w.z());
      V7 d;
      d << 0.5 * dq.w(), 0.5 * dq.vec(), Iinv_ * (I_ * w).cross(w);
      return d;
    };
    V7 y;
    y << q_.w(), q_.vec(), w_;
    const V7 k1 = f(y), k2 = f(y + 0.5 * h * k1), k3 = f(y + 0.5 * h * k2), k4 = f(y + h * k3);
    y += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    q_ = Eigen::Quaterniond(y[0], y[1], y[2], y[3]).normalized();
    w_ = y.tail<3>();
  }
  [[nodiscard]] const Eigen::Quaterniond& orientation() const { return q_; }

 private:
  Eigen::Matrix3d I_, Iinv_;
  Eigen::Quaterniond q_;
  Eigen::Vector3d w_;
};

}  // namespace

double maxAbsDifference(const Samples& a, const Samples& b) {
  double worst = 0.0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    const double d = std::abs(a[i] - b[i]);
    worst = std::max(worst, std::isfinite(d) ? d : 1e300);
  }
  return worst;
}

double medianSeconds(const std::function<void()>& body, const WorkPrecisionOptions& o) {
  std::vector<double> runs;
  for (int r = 0; r < std::max(1, o.repeats); ++r) {
    long count = 0;
    const double start = cpuNow();
    double elapsed = 0.0;
    do {
      body();
      ++count;
      elapsed = cpuNow() - start;
    } while (elapsed < o.minTimedSeconds);
    runs.push_back(elapsed / static_cast<double>(count));
  }
  std::nth_element(runs.begin(), runs.begin() + static_cast<long>(runs.size() / 2), runs.end());
  return runs[runs.size() / 2];
}

Samples slideReference(const SlideScenario& s) {
  const double g = kStandardGravity, th = s.tiltDeg * kDeg;
  const double a = g * (std::sin(th) - s.fd * std::cos(th));
  const double tStop = a < 0.0 ? -s.v0 / a : INFINITY;
  const bool restarts = std::tan(th) > s.fs;
  const double aDown = g * (std::sin(th) - s.fd * std::cos(th));
  Samples out(static_cast<std::size_t>(sampleCount(s.duration)));
  for (std::size_t k = 0; k < out.size(); ++k) {
    const double t = static_cast<double>(k) * kSampleInterval;
    if (t <= tStop) {
      out[k] = s.v0 * t + 0.5 * a * t * t;
    } else {
      const double sStop = s.v0 * tStop + 0.5 * a * tStop * tStop;
      const double tr = t - tStop;
      out[k] = restarts ? sStop + 0.5 * aDown * tr * tr : sStop;
    }
  }
  return out;
}

Samples pendulumReference(const PendulumScenario& p) {
  const double k = p.mass * kStandardGravity * p.arm / p.inertia(), c = p.fr / p.inertia();
  const auto f = [k, c](double, const Eigen::Vector2d& y) { return Eigen::Vector2d(y[1], -k * std::sin(y[0]) - c * y[1]); };
  Samples out(static_cast<std::size_t>(sampleCount(p.duration)));
  Eigen::Vector2d y(p.theta0Deg * kDeg, 0.0);
  out[0] = y[0];
  for (std::size_t i = 1; i < out.size(); ++i) {
    y = integrateReference(f, static_cast<double>(i - 1) * kSampleInterval, y, static_cast<double>(i) * kSampleInterval);
    out[i] = y[0];
  }
  return out;
}

std::vector<Record> runWorkPrecision(const WorkPrecisionOptions& o, const WorkProgress& progress) {
  std::vector<Record> out;
  const SlideScenario slide;
  PendulumScenario undamped, damped;
  damped.fr = 0.0005;
  const std::array<TumbleScenario, 2> tumbles{TumbleScenario{}, tennisRacketScenario()};

  const Samples slideRef = slideReference(slide);
  const Samples undampedRef = pendulumReference(undamped), dampedRef = pendulumReference(damped);
  std::array<std::vector<Eigen::Quaterniond>, 2> tumbleRefs;
  for (std::size_t i = 0; i < tumbles.size(); ++i)
    for (int k = 0; o.wants(tumbles[i].name) && k < sampleCount(tumbles[i].duration); ++k)
      tumbleRefs[i].push_back(TorqueFree::reference(tumbleRelease(tumbles[i]), tumbleInertia(tumbles[i]), k * kSampleInterval));

  // rk4 is the classic method of the other charts, applied to Euler's equations with the quaternion.
  constexpr std::array<const char*, 3> tumbleMethods{"constant-omega", "rk4", "torque-free"};
  const auto tumbleNote = [](std::string_view method) {
    return method == "constant-omega" ? "the paper's model: constant world angular velocity, closed form"
           : method == "rk4"          ? "classic RK4 on Euler's equations and the quaternion kinematics, renormalized"
                                      : "closed form: Jacobi elliptic body rate by the addition theorem, Simpson's rule on the angle about L";
  };
  const std::vector<int> rates = o.stepRates();
  for (int rate : rates)
    if (rate <= 0 || std::abs(rate * kSampleInterval - std::round(rate * kSampleInterval)) > 1e-9)
      throw std::invalid_argument("work-precision: a step rate of " + std::to_string(rate) +
                                  " Hz is not a whole number of steps per 0.1 s sample");
  std::size_t perRate = 0;
  if (o.wants("slide-with-stop")) perRate += kSlideMethods.size();
  for (const char* p : {"gear-pendulum", "gear-pendulum-damped"})
    if (o.wants(p)) perRate += Hinge::kMethods.size();
  for (const auto& t : tumbles)
    if (o.wants(t.name)) perRate += tumbleMethods.size();
  const int total = static_cast<int>(rates.size() * perRate);
  int done = 0;
  const auto tick = [&] { return !progress || progress(++done, total); };

  for (int rate : rates) {
    for (Method m : kSlideMethods) {
      if (!o.wants("slide-with-stop")) break;
      Record r{"slide-with-stop", std::string(name(m)), static_cast<double>(rate), 0, 0, "m", true, ""};
      Samples s;
      r.cpuPerSimSecond = medianSeconds([&] { s = runSlide(slide, m, rate); }, o) / slide.duration;
      r.error = maxAbsDifference(s, slideRef);
      out.push_back(r);
      if (!tick()) return out;
    }
    for (const auto* p : {&undamped, &damped}) {
      if (!o.wants(p->fr > 0 ? "gear-pendulum-damped" : "gear-pendulum")) continue;
      const Hinge hinge = makeHinge(*p);
      const double wn = hinge.naturalFrequency(hinge.torque(Eigen::Matrix3d::Identity(), worldGravity()));
      for (Method m : Hinge::kMethods) {
        Record r{p->fr > 0 ? "gear-pendulum-damped" : "gear-pendulum", std::string(name(m)), static_cast<double>(rate), 0, 0, "rad",
                 true, ""};
        Samples s;
        r.cpuPerSimSecond = medianSeconds([&] { s = runPendulum(*p, hinge, m, rate); }, o) / p->duration;
        r.error = maxAbsDifference(s, p->fr > 0 ? dampedRef : undampedRef);
        const StabilityReport st = checkStability(m, wn, p->fr / hinge.inertia(), 1.0 / rate);
        r.stable = st.stable;
        r.note = st.message;
        out.push_back(r);
        if (!tick()) return out;
      }
    }
    // Free flight: the paper's constant angular velocity (closed form, no steps), RK4 on Euler's
    // equations, and the closed-form torque-free rotation; the error is the largest orientation angle
    // off the reference at the samples.
    for (std::size_t i = 0; i < tumbles.size(); ++i) {
      const TumbleScenario& tumble = tumbles[i];
      if (!o.wants(tumble.name)) continue;
      const Eigen::Matrix3d inertia = tumbleInertia(tumble);
      const Release release = tumbleRelease(tumble);
      for (const char* method : tumbleMethods) {
        Record r{tumble.name, method, static_cast<double>(rate), 0, 0, "rad", true, tumbleNote(method)};
        std::vector<Eigen::Quaterniond> q;
        const int per = stepsPerSample(rate);
        const std::string_view which(method);
        const auto body = [&] {
          q.clear();
          q.push_back(release.orientation);
          std::optional<TorqueFree> tf;
          std::optional<EulerRk4> rk;
          if (which == "torque-free") tf.emplace(release, inertia);
          if (which == "rk4") rk.emplace(release, inertia);
          for (std::size_t k = 1; k < tumbleRefs[i].size(); ++k) {
            for (int j = 0; j < per; ++j) {
              if (which == "constant-omega") {
                // Evaluated every frame, as the workbench does for display.
                gSink = constantOmegaOrientation(release, (static_cast<double>(k - 1) * per + j + 1) / rate).w();
              } else if (which == "rk4") {
                rk->step(1.0 / rate);
              } else {
                tf->step(1.0 / rate);
              }
            }
            q.push_back(which == "constant-omega" ? constantOmegaOrientation(release, static_cast<double>(k) * kSampleInterval)
                        : rk                      ? rk->orientation()
                                                  : tf->orientation());
          }
        };
        r.cpuPerSimSecond = medianSeconds(body, o) / tumble.duration;
        for (std::size_t k = 0; k < q.size(); ++k) r.error = std::max(r.error, angleBetween(q[k], tumbleRefs[i][k]));
        out.push_back(r);
        if (!tick()) return out;
      }
    }
  }
  return out;
}

}  // namespace vaw::dyn
