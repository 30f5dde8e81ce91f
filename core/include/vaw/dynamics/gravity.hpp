#pragma once
#include <Eigen/Core>

#include "vaw/units.hpp"

namespace vaw::dyn {

// World gravity: z is up (docs/scene-format.md).
inline Eigen::Vector3d worldGravity() { return {0.0, 0.0, -kStandardGravity}; }

// Gravity scale per motion kind (docs/physics.md, "Gravity scale"): the paper found 0.2-0.3 right for free flight
// in a headset and no scaling for rotation on the base.
struct GravityScales {
  double freeFlight = 0.25;
  double slide = 1.0;
  double rotation = 1.0;
};

// The gravity a part on a hand-held base feels in the base's frame: g - a_base when inertial forces are
// on (translational acceleration of the base at the part; rotational terms are left out), else g.
inline Eigen::Vector3d effectiveGravity(const Eigen::Vector3d& g, const Eigen::Vector3d& baseAcceleration,
                                        bool inertialForces) {
  return inertialForces ? Eigen::Vector3d(g - baseAcceleration) : g;
}

}  // namespace vaw::dyn
