#pragma once
// Time-stepping methods for the reduced models (PHYSICS.md sections 3-4). A model with one coordinate
// x and its rate v evolves as x'' = f(t, x, v); every method here advances (x, v) by one step h.
// Header-only and templated on f so a step costs a few nanoseconds (no virtual call, no allocation).
#include <array>
#include <cmath>
#include <string_view>

namespace vaw::dyn {

enum class Method {
  PaperExplicit,      // paper eq. 4b-c / 11: x += v h + a h^2/2, v += a h, with a from the step's start
  SemiImplicitEuler,  // v += a h, then x += v h (symplectic)
  VelocityVerlet,     // half kick, drift, half kick (symplectic for position-only forces)
  RK4,                // classic fourth-order Runge-Kutta
  Exact,              // closed form where the acceleration is constant within the step (slides)
};
inline constexpr std::array kAllMethods{Method::PaperExplicit, Method::SemiImplicitEuler, Method::VelocityVerlet,
                                        Method::RK4, Method::Exact};

constexpr std::string_view name(Method m) {
  switch (m) {
    case Method::PaperExplicit: return "paper-explicit";
    case Method::SemiImplicitEuler: return "semi-implicit-euler";
    case Method::VelocityVerlet: return "velocity-verlet";
    case Method::RK4: return "rk4";
    case Method::Exact: return "exact";
  }
  return "?";
}
bool parseMethod(std::string_view text, Method& out);

// A coordinate (m or rad; a scalar or an Eigen vector) and its rate.
template <class T>
struct PhaseOf {
  T x{};
  T v{};
};
using Phase = PhaseOf<double>;

// One step of x'' = f(t, x, v). Exact is the paper's formula, which is exact only when f is constant
// over the step; models that offer Exact guarantee that.
template <class T, class F>
inline PhaseOf<T> step(Method m, const F& f, double t, PhaseOf<T> s, double h) {
  switch (m) {
    case Method::PaperExplicit:
    case Method::Exact: {
      const T a = f(t, s.x, s.v);
      return {s.x + s.v * h + 0.5 * h * h * a, s.v + h * a};
    }
    case Method::SemiImplicitEuler: {
      const T v = s.v + h * f(t, s.x, s.v);
      return {s.x + h * v, v};
    }
    case Method::VelocityVerlet: {
      const T a0 = f(t, s.x, s.v);
      const T vHalf = s.v + 0.5 * h * a0;
      const T x = s.x + h * vHalf;
      // A velocity-dependent force (viscous friction) is evaluated at the half-step velocity.
      return {x, vHalf + 0.5 * h * f(t + h, x, vHalf)};
    }
    case Method::RK4: {
      const T k1x = s.v, k1v = f(t, s.x, s.v);
      const T k2x = s.v + 0.5 * h * k1v;
      const T k2v = f(t + 0.5 * h, T(s.x + 0.5 * h * k1x), k2x);
      const T k3x = s.v + 0.5 * h * k2v;
      const T k3v = f(t + 0.5 * h, T(s.x + 0.5 * h * k2x), k3x);
      const T k4x = s.v + h * k3v;
      const T k4v = f(t + h, T(s.x + h * k3x), k4x);
      return {s.x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x), s.v + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v)};
    }
  }
  return s;
}

// Number of evaluations of f per step, for cost accounting.
constexpr int evaluations(Method m) {
  switch (m) {
    case Method::PaperExplicit:
    case Method::Exact:
    case Method::SemiImplicitEuler: return 1;
    case Method::VelocityVerlet: return 2;
    case Method::RK4: return 4;
  }
  return 1;
}

}  // namespace vaw::dyn
