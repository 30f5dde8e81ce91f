#pragma once
// Jacobi elliptic functions and the complete elliptic integral of the first kind, for the closed-form
// torque-free rotation (free_flight.hpp, docs/physics.md). Every function takes the complementary
// parameter kc2 = 1 - k^2 rather than k, so that motions close to the separatrix (k -> 1, a spin near
// the intermediate axis) keep their accuracy.
namespace vaw::dyn {

struct Jacobi {
  double sn = 0.0;
  double cn = 1.0;
  double dn = 1.0;
};

// Carlson's symmetric integral R_F(x, y, z) (Carlson 1995, duplication with the fifth-order series);
// x, y, z >= 0, at most one of them zero. Relative error below 1e-15.
double carlsonRF(double x, double y, double z);

// K(k) = R_F(0, kc2, 1) for 0 < kc2 <= 1; infinite at kc2 = 0.
double ellipticK(double kc2);

// sn, cn, dn of u for the parameter k^2 = 1 - kc2, 0 <= kc2 <= 1, by Bulirsch's descending Gauss
// transformation; cn and dn keep their relative accuracy as k -> 1. u is first reduced by the period 4K.
Jacobi jacobi(double u, double kc2);

// The addition theorem: sn, cn, dn of u + v from those of u and v (A&S 16.17.1-3), with the
// denominator 1 - k^2 sn^2(u) sn^2(v) written as a sum of squares so that it keeps its relative accuracy
// near the separatrix. Exact algebra: a step of the torque-free rotation is one call with v fixed.
inline Jacobi jacobiAdd(const Jacobi& a, const Jacobi& b, double k2, double kc2) {
  const double s2 = a.sn * a.sn * b.sn * b.sn;
  const double d = 1.0 / (a.cn * a.cn + a.sn * a.sn * b.cn * b.cn + kc2 * s2);
  return {(a.sn * b.cn * b.dn + b.sn * a.cn * a.dn) * d, (a.cn * b.cn - a.sn * b.sn * a.dn * b.dn) * d,
          (a.dn * b.dn - k2 * a.sn * b.sn * a.cn * b.cn) * d};
}

}  // namespace vaw::dyn
