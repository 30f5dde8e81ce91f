#include "vaw/dynamics/elliptic.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

namespace vaw::dyn {

double carlsonRF(double x, double y, double z) {
  // The error after the loop is about tol^6 / 4: 0.0025 gives 6e-17.
  constexpr double tol = 0.0025;
  for (int i = 0; i < 100; ++i) {
    const double sx = std::sqrt(x), sy = std::sqrt(y), sz = std::sqrt(z);
    const double lambda = sx * (sy + sz) + sy * sz;
    x = 0.25 * (x + lambda);
    y = 0.25 * (y + lambda);
    z = 0.25 * (z + lambda);
    const double mean = (x + y + z) / 3.0;
    const double dx = (mean - x) / mean, dy = (mean - y) / mean, dz = (mean - z) / mean;
    if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) <= tol) {
      const double e2 = dx * dy - dz * dz, e3 = dx * dy * dz;
      return (1.0 + (e2 / 24.0 - 0.1 - 3.0 / 44.0 * e3) * e2 + e3 / 14.0) / std::sqrt(mean);
    }
  }
  return std::numeric_limits<double>::quiet_NaN();
}

double ellipticK(double kc2) {
  if (!(kc2 > 0.0)) return std::numeric_limits<double>::infinity();
  return carlsonRF(0.0, kc2, 1.0);
}

Jacobi jacobi(double u, double kc2) {
  kc2 = std::clamp(kc2, 0.0, 1.0);
  if (kc2 == 1.0) return {std::sin(u), std::cos(u), 1.0};
  if (kc2 == 0.0) {
    const double sech = 1.0 / std::cosh(u);
    return {std::tanh(u), sech, sech};
  }
  // sn and cn have the period 4K: reducing u keeps the angle below small enough for full accuracy.
  if (std::abs(u) > 2.0) {
    const double period = 4.0 * ellipticK(kc2);
    u -= period * std::nearbyint(u / period);
  }
  // Bulirsch (Numer. Math. 7, 1965): Gauss transformations down to a circular function, then back up
  // through the ratio cn / sn and dn, never through an arcsine, so that cn and dn keep their relative
  // accuracy where sn is close to 1 (k close to 1: a spin near the intermediate axis). The arcsine
  // descent of A&S 16.4 loses half the digits there.
  std::array<double, 24> mean{}, root{};
  double a = 1.0, m = kc2, c = 1.0;
  std::size_t levels = 0;
  while (levels < mean.size()) {
    mean[levels] = a;
    m = std::sqrt(m);
    root[levels] = m;
    ++levels;
    c = 0.5 * (a + m);
    if (std::abs(a - m) <= 1e-8 * a) break;  // the error is the square of this: 1e-16
    m *= a;
    a = c;
  }
  const double v = u * c;
  double sn = std::sin(v), cn = std::cos(v), dn = 1.0;
  if (sn != 0.0) {
    double ratio = cn / sn;  // carried up as cn / sn of each level's argument
    c *= ratio;
    for (std::size_t i = levels; i-- > 0;) {
      const double b = mean[i];
      ratio *= c;
      c *= dn;
      dn = (root[i] + ratio) / (b + ratio);
      ratio = c / b;
    }
    const double s = 1.0 / std::sqrt(c * c + 1.0);
    sn = sn >= 0.0 ? s : -s;
    cn = c * sn;
  }
  return {sn, cn, dn};
}

}  // namespace vaw::dyn
