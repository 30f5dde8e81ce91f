#pragma once
// Live edits of a running world: gravity scales, friction, the rotation method, the step rate. The
// workbench's panels change these while the simulation runs; the world applies an edit between two steps
// (World::apply), logs it with the step it took effect at, and a session records it, so a replay applies
// it at the same step and stays bit for bit.
//
// The rule for parts already in a state (docs/simulation.md, "Live edits"): every model reads its gravity,
// friction and method afresh each step, so an edit takes effect from the next step; a part in free flight,
// whose path is a closed form from its release, is re-based: its flight restarts at the edit's time from
// its current position, velocity, orientation and angular velocity under the new gravity.
#include <cstdint>
#include <optional>
#include <string>
#include <variant>

#include "vaw/assembly.hpp"
#include "vaw/dynamics/gravity.hpp"
#include "vaw/dynamics/integrators.hpp"

namespace vaw::sim {

using vaw::FrictionValues;

struct GravityEdit {
  dyn::GravityScales scales;
};
struct MaterialFrictionEdit {
  std::string material;
  FrictionValues friction;
};
// A per-part override of its material's friction; none: the part follows its material again.
struct PartFrictionEdit {
  PartId part = 0;
  std::optional<FrictionValues> friction;
};
// The integration method of rotation about an axis (slides are in closed form).
struct MethodEdit {
  dyn::Method rotation = dyn::Method::RK4;
};
struct RateEdit {
  double rate = 90.0;  // Hz
};

using Edit = std::variant<GravityEdit, MaterialFrictionEdit, PartFrictionEdit, MethodEdit, RateEdit>;

struct EditRecord {
  std::uint64_t step = 0;  // the first step that ran with the edit
  double t = 0.0;          // s, the world's time when it was applied
  Edit edit;
};

// One line for logs, the timeline and messages, e.g. "friction of steel: static 0.3, kinetic 0.2, ...".
std::string describe(const Edit& e, const Assembly& assembly);

// Empty when `e` is valid for `assembly`; otherwise which rule it breaks, with the value.
std::string validate(const Edit& e, const Assembly& assembly);
// The same rules for a set of friction coefficients alone (the scene loader's and the panels' check).
std::string validateFriction(const FrictionValues& f);

// The methods rotation about an axis can use (its torque depends on the angle: no closed form).
bool rotationSupports(dyn::Method m);

inline constexpr double kMinRate = 1.0;      // Hz
inline constexpr double kMaxRate = 10000.0;  // Hz
inline constexpr double kMaxGravityScale = 10.0;

}  // namespace vaw::sim
