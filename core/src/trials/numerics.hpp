#pragma once
// The few numerical tools the trial analysis needs. Nothing here is generic enough to warrant a
// dependency: the fits are one-dimensional searches nested at most two deep (docs/trials.md says why).
#include <functional>

namespace vaw::trials::detail {

double normalCdf(double z);
double normalQuantile(double p);                 // inverse of normalCdf, 0 < p < 1
double studentTQuantile(double p, double dof);   // 0 < p < 1, dof > 0
double chiSquare1Quantile(double p);             // one degree of freedom
// P(X <= k) for X ~ Binomial(n, 1/2).
double binomialHalfCdf(int k, int n);

// The minimum of f on [a, b] by golden-section search, to within tol in x. For a unimodal f it finds
// the minimum; elsewhere a local one, which is why callers bracket with a grid first where that matters.
double goldenMinimize(const std::function<double(double)>& f, double a, double b, double tol);

// A root of f in [a, b], where f(a) and f(b) differ in sign, by bisection to within tol.
double bisectRoot(const std::function<double(double)>& f, double a, double b, double tol);

}  // namespace vaw::trials::detail
