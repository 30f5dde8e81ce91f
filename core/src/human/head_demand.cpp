#include "vaw/human/head_demand.hpp"

#include <cmath>
#include <stdexcept>

namespace vaw::human {

namespace {

constexpr double kDegPerRad = 180.0 / M_PI;

void requirePositive(double v, const char* what) {
  if (!(v > 0.0) || !std::isfinite(v)) throw std::invalid_argument(std::string("head demand: ") + what + " must be positive");
}

}  // namespace

// With a = g / (2 d) the angle is atan(a t^2); the derivatives below are those of that closed form.
double viewAngle(double t, double g, double d) { return std::atan(g * t * t / (2.0 * d)); }

double viewRate(double t, double g, double d) {
  const double a = g / (2.0 * d), u = a * t * t;
  return 2.0 * a * t / (1.0 + u * u);
}

double viewAcceleration(double t, double g, double d) {
  const double a = g / (2.0 * d), u = a * t * t;
  return 2.0 * a * (1.0 - 3.0 * u * u) / ((1.0 + u * u) * (1.0 + u * u));
}

HeadDemand headDemand(double g, const ViewingGeometry& geometry) {
  requirePositive(g, "gravity");
  requirePositive(geometry.distance_m, "viewing distance");
  requirePositive(geometry.fallHeight_m, "fall height");
  const double d = geometry.distance_m, a = g / (2.0 * d);
  HeadDemand out;
  out.fallTime_s = std::sqrt(2.0 * geometry.fallHeight_m / g);
  out.finalAngle_deg = kDegPerRad * std::atan(geometry.fallHeight_m / d);
  // The rate rises while a t^2 < 1/sqrt(3) (theta < 30 degrees) and falls after; a fall that lands
  // before then peaks at the landing.
  const double tPeak = std::pow(3.0 * a * a, -0.25);
  out.peakRateTime_s = std::min(tPeak, out.fallTime_s);
  out.peakRate_deg_s = kDegPerRad * viewRate(out.peakRateTime_s, g, d);
  // theta'' = 2a (1 - 3u^2) / (1 + u^2)^2 starts at its largest magnitude, 2a = g / d; its most negative
  // value is -(9/16) g / d, smaller in magnitude.
  out.peakAcceleration_deg_s2 = kDegPerRad * g / d;
  out.peakAccelerationTime_s = 0.0;
  return out;
}

ScaleRecommendation recommendScale(const ViewingGeometry& geometry, const HeadLimits& limits, FollowAxis axis, double g) {
  ScaleRecommendation r;
  r.atFullGravity = headDemand(g, geometry);
  r.rateLimit_deg_s = axis == FollowAxis::Pitch ? limits.pitchRate_deg_s : limits.yawRate_deg_s;
  requirePositive(r.rateLimit_deg_s, "head rate limit");
  // Scaling gravity by s scales time by 1/sqrt(s): rates grow with sqrt(s), accelerations with s.
  const double ratio = r.rateLimit_deg_s / r.atFullGravity.peakRate_deg_s;
  r.maxScale = ratio * ratio;
  r.limitedBy = axis == FollowAxis::Pitch ? "pitch rate" : "yaw rate";
  if (limits.acceleration_deg_s2) {
    requirePositive(*limits.acceleration_deg_s2, "head acceleration limit");
    const double byAcceleration = *limits.acceleration_deg_s2 / r.atFullGravity.peakAcceleration_deg_s2;
    if (byAcceleration < r.maxScale) {
      r.maxScale = byAcceleration;
      r.limitedBy = "acceleration";
    }
  }
  r.recommendedScale = std::min(1.0, r.maxScale);
  return r;
}

}  // namespace vaw::human
