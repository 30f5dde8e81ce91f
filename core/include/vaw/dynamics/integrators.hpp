#pragma once
// Time-stepping methods for the reduced models (docs/physics.md, "Integrators"). A model with one
// coordinate x and its rate v evolves as x'' = f(t, x, v); every method here advances (x, v) by one
// step h. Header-only and templated on f so a step costs a few nanoseconds (no virtual call, no
// allocation).
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace vaw::dyn {

enum class Method {
  PaperExplicit,      // paper eq. 4b-c / 11: x += v h + a h^2/2, v += a h, with a from the step's start
  SemiImplicitEuler,  // v += a h, then x += v h (symplectic)
  VelocityVerlet,     // half kick, drift, half kick; the second kick implicit in viscous friction
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

// The methods a model can use. Each model publishes its list (kSlideMethods in slide.hpp,
// Hinge::kMethods in hinge.hpp); settings and the work-precision code choose from that list, so a
// method a model cannot use is refused where it is chosen, with the list in the message, and never
// reaches a step.
using MethodList = std::span<const Method>;
constexpr bool supports(MethodList list, Method m) { return std::find(list.begin(), list.end(), m) != list.end(); }
// "paper-explicit, semi-implicit-euler, velocity-verlet or rk4"
std::string describe(MethodList list);
// The method named `text` if it is in `list`.
std::optional<Method> parseMethod(std::string_view text, MethodList list);

// A coordinate (m or rad; a scalar or an Eigen vector) and its rate.
template <class T>
struct PhaseOf {
  T x{};
  T v{};
};
using Phase = PhaseOf<double>;

// One step of x'' = f(t, x, v). Exact is the paper's formula, which is exact only when f is constant
// over the step; models that offer Exact guarantee that. dfdv is the model's constant df/dv (viscous
// friction: -f_r / J), the part of f that velocity Verlet solves implicitly in its second half kick;
// the other methods do not need it.
template <class T, class F>
inline PhaseOf<T> step(Method m, const F& f, double t, PhaseOf<T> s, double h, double dfdv = 0.0) {
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
      // v1 = vHalf + h/2 f(x, v1) with f affine in v: solved for v1, the friction is the trapezoidal
      // rule's and the method keeps its second order (explicit at vHalf it drops to first order).
      const T fHalf = f(t + h, x, vHalf);
      return {x, T((vHalf + 0.5 * h * (fHalf - dfdv * vHalf)) / (1.0 - 0.5 * h * dfdv))};
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
