#pragma once
// Sliding on the base with Coulomb friction (docs/physics.md, "Sliding", with its corrections to the paper):
// 1-D along an axis (or the line of two planes) and 2-D on a plane. The constraint geometry is given
// in world coordinates for the current step, recomputed by the caller from the (possibly moving) base.
#include <Eigen/Geometry>
#include <array>
#include <optional>

#include "vaw/dynamics/integrators.hpp"

namespace vaw::dyn {

// Every method: the acceleration is constant between the events a step locates, so Exact is the
// closed form (on a plane only while the velocity is parallel to the slope; otherwise the paper's scheme).
inline constexpr std::array kSlideMethods = kAllMethods;

struct Friction {
  double fs = 0.3;  // static coefficient
  double fd = 0.2;  // kinetic coefficient, <= fs
};

// Allowed direction along an axis through e1, e2: unit(e2 - e1) flipped so that u.G >= 0 (paper eq. 2a,
// normalized as the paper forgets to). Zero-length axis: returns nothing.
std::optional<Eigen::Vector3d> axisDirection(const Eigen::Vector3d& e1, const Eigen::Vector3d& e2, const Eigen::Vector3d& g);
// Line of two planes: unit(n1 x n2), flipped so that u.G >= 0; parallel planes: nothing.
std::optional<Eigen::Vector3d> lineOfPlanes(const Eigen::Vector3d& n1, const Eigen::Vector3d& n2, const Eigen::Vector3d& g);
// The static friction angle: beta below which (between G and the allowed direction) a part starts.
double staticFrictionAngle(double fs);  // rad, 90 deg - atan(fs)

enum class SlideEvent { None, Started, Stopped, ReachedLower, ReachedUpper, LostContact };

// ---- 1-D ----
struct AxisSlideState {
  double s = 0.0;        // m along u from the reference point
  double v = 0.0;        // m/s along u
  bool moving = false;   // false = sticking
};

struct AxisSlideInput {
  Eigen::Vector3d u = Eigen::Vector3d::UnitX();  // unit axis, world
  Eigen::Vector3d g = Eigen::Vector3d::Zero();   // gravity (scaled, effective), world
  double lower = -1e300, upper = 1e300;          // bounds on s (edge, shoulder, end of shaft)
};

struct SlideStep {
  SlideEvent event = SlideEvent::None;
  double eventTime = 0.0;  // s after the step's start, when event != None
};

// Advances by h. Events (start, stop, reaching a bound) are located inside the step; at a bound the
// state is left exactly on it with its velocity and the step ends there (the caller decides what
// the bound means). The acceleration is constant within a step, so Method::Exact is the closed form.
SlideStep stepAxisSlide(AxisSlideState& state, const AxisSlideInput& in, const Friction& f, double h, Method m);

// Tangential and normal parts of g for the axis u: G_t = g.u (signed), |G_n|.
struct AxisGravity { double along; double normal; };
AxisGravity splitGravity(const Eigen::Vector3d& u, const Eigen::Vector3d& g);

// The slide inputs for this step from the constraint geometry in the base's frame and the base's
// current pose: a hand-held base turns the axis and the plane under the part every step.
AxisSlideInput axisInWorld(const Eigen::Vector3d& directionInBase, const Eigen::Isometry3d& basePose, const Eigen::Vector3d& g);

// ---- 2-D ----
struct PlaneSlideState {
  Eigen::Vector2d p = Eigen::Vector2d::Zero();  // m in the plane basis (e1, e2)
  Eigen::Vector2d v = Eigen::Vector2d::Zero();  // m/s
  bool moving = false;
};

struct PlaneSlideInput {
  Eigen::Vector3d n = Eigen::Vector3d::UnitZ();   // unit normal of the base surface, pointing out of it, world
  Eigen::Vector3d e1 = Eigen::Vector3d::UnitX();  // in-plane unit basis, world (e1 x e2 = n)
  Eigen::Vector3d e2 = Eigen::Vector3d::UnitY();
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
};

// normalInBase: the base surface's outward normal in the base frame. The in-plane basis is fixed in the
// base (so plane coordinates stay meaningful while the base turns).
PlaneSlideInput planeInWorld(const Eigen::Vector3d& normalInBase, const Eigen::Isometry3d& basePose, const Eigen::Vector3d& g);

// Kinetic friction opposes the velocity (not the slope). A stop inside the step is located from the
// speed's rate of change; gravity pulling the part off the surface (n.g > 0) is LostContact.
// Method::Exact is exact when the velocity is parallel to the slope (released from rest, base still);
// otherwise it is the paper's scheme.
SlideStep stepPlaneSlide(PlaneSlideState& state, const PlaneSlideInput& in, const Friction& f, double h, Method m);

}  // namespace vaw::dyn
