#pragma once
// How fast the head must turn to keep a falling part in view, and the largest gravity scale that keeps
// that within what a head can do (docs/head-demand.md has the derivation, the sources and an example).
//
// The part is released at eye level, d metres in front of the eye, and falls h metres under gravity G.
// The viewing angle below the horizontal is theta(t) = atan(G t^2 / (2 d)) until it lands at
// t_end = sqrt(2 h / G). Every rate scales with sqrt(G) and every acceleration with G, which is what
// makes the recommended scale a closed form.
#include <optional>
#include <string>

#include "vaw/units.hpp"

namespace vaw::human {

struct ViewingGeometry {
  double distance_m = 1.0;     // eye to the falling part, horizontally
  double fallHeight_m = 1.0;   // how far below eye level the fall ends (the floor, a table)
};

// Peak head angular speeds from Durlach et al. (1995), the source the paper relies on; the paper adds
// that a helmet lowers them, so they are settings. The source gives no acceleration limit: leave it
// unset unless you have a figure for your headset and population.
struct HeadLimits {
  double yawRate_deg_s = 600.0;
  double pitchRate_deg_s = 300.0;
  std::optional<double> acceleration_deg_s2;
};

// A vertical fall is followed by pitching the head; a part crossing the view sideways by yawing it.
enum class FollowAxis { Pitch, Yaw };

struct HeadDemand {
  double fallTime_s = 0.0;
  double finalAngle_deg = 0.0;        // atan(h / d), whatever the gravity
  double peakRate_deg_s = 0.0;
  double peakRateTime_s = 0.0;        // the interior maximum, or the landing when that comes first
  double peakAcceleration_deg_s2 = 0.0;  // G / d, at release (the paper's eq. 12 is exact there)
  double peakAccelerationTime_s = 0.0;
};

// theta(t), theta'(t), theta''(t) in rad, rad/s, rad/s^2 for gravity g (m/s^2) at distance d (m).
double viewAngle(double t, double g, double d);
double viewRate(double t, double g, double d);
double viewAcceleration(double t, double g, double d);

// The demand of following the whole fall under gravity g. Throws std::invalid_argument on a
// non-positive g, distance or height (callers validate user input first).
HeadDemand headDemand(double g, const ViewingGeometry& geometry);

struct ScaleRecommendation {
  HeadDemand atFullGravity;     // the demand at scale 1
  double rateLimit_deg_s = 0.0; // the limit of the axis followed
  double maxScale = 0.0;        // the largest scale whose demand is within every limit (may exceed 1)
  double recommendedScale = 0.0;  // min(1, maxScale): nobody asks parts to fall faster than real
  std::string limitedBy;        // "pitch rate", "yaw rate" or "acceleration"
};

ScaleRecommendation recommendScale(const ViewingGeometry& geometry, const HeadLimits& limits = {},
                                   FollowAxis axis = FollowAxis::Pitch, double g = kStandardGravity);

}  // namespace vaw::human
