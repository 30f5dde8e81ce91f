#include "numerics.hpp"

#include <cmath>
#include <stdexcept>
#include <unsupported/Eigen/SpecialFunctions>

namespace vaw::trials::detail {

double normalCdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

double normalQuantile(double p) {
  if (!(p > 0.0 && p < 1.0)) throw std::invalid_argument("normalQuantile: p outside (0, 1)");
  return Eigen::numext::ndtri(p);
}

double studentTQuantile(double p, double dof) {
  if (!(p > 0.0 && p < 1.0) || !(dof > 0.0)) throw std::invalid_argument("studentTQuantile: p outside (0, 1) or dof <= 0");
  if (p < 0.5) return -studentTQuantile(1.0 - p, dof);
  // For t >= 0, P(T <= t) = 1 - I_{dof / (dof + t^2)}(dof / 2, 1 / 2) / 2, which rises with t.
  const auto cdf = [dof](double t) { return 1.0 - 0.5 * Eigen::numext::betainc(dof / 2.0, 0.5, dof / (dof + t * t)); };
  double hi = 1.0;
  while (cdf(hi) < p) hi *= 2.0;
  return bisectRoot([&](double t) { return cdf(t) - p; }, 0.0, hi, 1e-12 * hi);
}

double chiSquare1Quantile(double p) {
  const double z = normalQuantile(0.5 + 0.5 * p);
  return z * z;
}

double binomialHalfCdf(int k, int n) {
  if (k < 0) return 0.0;
  if (k >= n) return 1.0;
  double sum = 0.0;
  for (int i = 0; i <= k; ++i)
    sum += std::exp(std::lgamma(n + 1.0) - std::lgamma(i + 1.0) - std::lgamma(n - i + 1.0) - n * std::log(2.0));
  return std::min(sum, 1.0);
}

double goldenMinimize(const std::function<double(double)>& f, double a, double b, double tol) {
  const double r = (std::sqrt(5.0) - 1.0) / 2.0;
  double c = b - r * (b - a), d = a + r * (b - a);
  double fc = f(c), fd = f(d);
  while (b - a > tol) {
    if (fc <= fd) {
      b = d;
      d = c;
      fd = fc;
      c = b - r * (b - a);
      fc = f(c);
    } else {
      a = c;
      c = d;
      fc = fd;
      d = a + r * (b - a);
      fd = f(d);
    }
  }
  return fc <= fd ? c : d;
}

double bisectRoot(const std::function<double(double)>& f, double a, double b, double tol) {
  double fa = f(a);
  if ((fa > 0.0) == (f(b) > 0.0)) throw std::invalid_argument("bisectRoot: f(a) and f(b) have the same sign");
  while (b - a > tol) {
    const double m = 0.5 * (a + b), fm = f(m);
    if ((fm > 0.0) == (fa > 0.0)) {
      a = m;
      fa = fm;
    } else {
      b = m;
    }
  }
  return 0.5 * (a + b);
}

}  // namespace vaw::trials::detail
