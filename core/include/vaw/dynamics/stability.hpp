#pragma once
// Where explicit methods fail (docs/physics.md, "Stability limits"): for the linearized oscillator
// x'' = -wn^2 x - c x' one step of a method is a 2x2 linear map; the method is stable when that map's
// spectral radius is at most 1. The workbench calls checkStability before stepping a part so it can
// warn before the part explodes.
#include <string>

#include "vaw/dynamics/integrators.hpp"

namespace vaw::dyn {

// Spectral radius of one step of `m` applied to x'' = -wn^2 x - c x', measured by stepping the two
// basis states through the method itself (so it is exactly what the code does).
double spectralRadius(Method m, double wn, double c, double h);

// Largest wn*h for which the method is stable (spectral radius <= 1 + 1e-14), by bisection, for the
// damping ratio c / wn (0 = undamped). 0 when no step is stable (the paper's scheme, undamped).
double stabilityLimit(Method m, double dampingRatio = 0.0);

struct StabilityReport {
  bool stable = true;
  double spectralRadius = 0.0;
  double wnDt = 0.0;          // the step measured in natural periods' radians
  double limitWnDt = 0.0;     // the method's limit
  double margin = 0.0;        // limitWnDt / wnDt (> 1 stable); 0 when no step is stable
  double growthPerSecond = 1.0;  // amplitude factor per simulated second (rho^(1/h))
  std::string message;
};

StabilityReport checkStability(Method m, double wn, double c, double h);

}  // namespace vaw::dyn
