#pragma once
// Adaptive Dormand-Prince 5(4) integration (Dormand & Prince 1980; Hairer, Norsett & Wanner, Solving
// ODEs I, II.5), used as the reference solution when measuring the error of the fast methods.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vaw::dyn {

struct ReferenceOptions {
  double relTol = 1e-12;
  double absTol = 1e-12;
  double initialStep = 1e-4;
  long maxSteps = 50'000'000;
};

struct ReferenceStats {
  long accepted = 0;
  long rejected = 0;
};

// Integrates y' = f(t, y) from t0 to t1 and returns y(t1). f: (double, const V&) -> V.
// Lands exactly on t1. Throws std::runtime_error if the step size underflows.
template <class V, class F>
V integrateReference(const F& f, double t0, V y, double t1, const ReferenceOptions& o = {}, ReferenceStats* stats = nullptr) {
  static constexpr double c2 = 1.0 / 5, c3 = 3.0 / 10, c4 = 4.0 / 5, c5 = 8.0 / 9;
  static constexpr double a21 = 1.0 / 5;
  static constexpr double a31 = 3.0 / 40, a32 = 9.0 / 40;
  static constexpr double a41 = 44.0 / 45, a42 = -56.0 / 15, a43 = 32.0 / 9;
  static constexpr double a51 = 19372.0 / 6561, a52 = -25360.0 / 2187, a53 = 64448.0 / 6561, a54 = -212.0 / 729;
  static constexpr double a61 = 9017.0 / 3168, a62 = -355.0 / 33, a63 = 46732.0 / 5247, a64 = 49.0 / 176,
                          a65 = -5103.0 / 18656;
  static constexpr double b1 = 35.0 / 384, b3 = 500.0 / 1113, b4 = 125.0 / 192, b5 = -2187.0 / 6784, b6 = 11.0 / 84;
  static constexpr double e1 = 71.0 / 57600, e3 = -71.0 / 16695, e4 = 71.0 / 1920, e5 = -17253.0 / 339200,
                          e6 = 22.0 / 525, e7 = -1.0 / 40;
  double t = t0;
  double h = std::min(o.initialStep, t1 - t0);
  if (h <= 0.0) return y;
  V k1 = f(t, y);
  long steps = 0;
  while (t < t1) {
    if (++steps > o.maxSteps) throw std::runtime_error("reference integration: too many steps");
    if (t + h > t1) h = t1 - t;
    const V k2 = f(t + c2 * h, (y + h * a21 * k1).eval());
    const V k3 = f(t + c3 * h, (y + h * (a31 * k1 + a32 * k2)).eval());
    const V k4 = f(t + c4 * h, (y + h * (a41 * k1 + a42 * k2 + a43 * k3)).eval());
    const V k5 = f(t + c5 * h, (y + h * (a51 * k1 + a52 * k2 + a53 * k3 + a54 * k4)).eval());
    const V k6 = f(t + h, (y + h * (a61 * k1 + a62 * k2 + a63 * k3 + a64 * k4 + a65 * k5)).eval());
    const V yNew = (y + h * (b1 * k1 + b3 * k3 + b4 * k4 + b5 * k5 + b6 * k6)).eval();
    const V k7 = f(t + h, yNew);
    const V err = (h * (e1 * k1 + e3 * k3 + e4 * k4 + e5 * k5 + e6 * k6 + e7 * k7)).eval();
    double norm = 0.0;
    for (Eigen::Index i = 0; i < y.size(); ++i) {
      const double sc = o.absTol + o.relTol * std::max(std::abs(y[i]), std::abs(yNew[i]));
      norm += (err[i] / sc) * (err[i] / sc);
    }
    norm = std::sqrt(norm / static_cast<double>(y.size()));
    if (norm <= 1.0) {
      t += h;
      y = yNew;
      k1 = k7;  // first-same-as-last
      if (stats) ++stats->accepted;
    } else if (stats) {
      ++stats->rejected;
    }
    const double factor = norm == 0.0 ? 5.0 : std::clamp(0.9 * std::pow(norm, -0.2), 0.2, 5.0);
    h *= factor;
    if (t < t1 && h < 1e-14 * std::max(1.0, std::abs(t))) throw std::runtime_error("reference integration: step size underflow");
  }
  return y;
}

}  // namespace vaw::dyn
