#pragma once
// From the headset's hands to the world's input (docs/vr.md, "Input"): plain C++, no OpenXR and no Qt, so the
// mapping is tested on its own.
//
// - A tracked hand closes by a pinch (thumb tip to index tip below pinchClose, open again above pinchOpen) or
//   a closed grip (the middle, ring and little finger tips within gripClose of the palm on average, open
//   again beyond gripOpen); the gap between the thresholds is the hysteresis that keeps a trembling pinch
//   from grabbing and dropping. A controller closes while its select is pressed.
// - The hand's pose for the world: a pinch holds at the point between the thumb and index tips, a grip at
//   the palm, a controller at its grip pose; the orientation is the palm's (the grip's).
// - The right hand grabs parts (the world takes the nearest grabbable part within reach). The left hand
//   holds the base when it closes near it (within baseReach of its bounds): the base then follows the left
//   hand, kept from going lower than it stood at load as the desktop's base is. The left hand closing while
//   the right is closed and holds nothing joins it on a two-hand part.
// - On the step a hand opens, both hands' inputs carry the velocity their tracker measured (joint velocities
//   flagged valid, or the controller's), which the world then releases with; without valid velocities the
//   world's windowed estimate applies. Nothing is scaled.
// - A hand the headset does not see (tracking lost, no input focus) keeps its last pose and state, so a held
//   part is neither dropped nor thrown by a glitch.
#include <array>
#include <optional>

#include "vaw/sim/world.hpp"
#include "vaw/ui/xr.hpp"

namespace vaw::xr {

struct InputSettings {
  double pinchClose = 0.025, pinchOpen = 0.045;  // m, thumb tip to index tip
  double gripClose = 0.050, gripOpen = 0.070;    // m, mean of the middle, ring and little tips to the palm
  double baseReach = 0.08;                       // m, from the left hand to the base's bounds
};

class HandMapper {
 public:
  HandMapper(const Assembly& assembly, InputSettings settings);

  // The input of the next step from the hands at its end time. `world` is the world before the step (the
  // base's pose, what the hands hold); the hoist is the desktop's (the panel drives it while the wearer works).
  [[nodiscard]] sim::Input next(const HandsSample& hands, const sim::World& world, const sim::HoistInput& hoist);

  // Whether each hand (0 left, 1 right) is closed, and whether the left hand holds the base.
  [[nodiscard]] bool closed(int hand) const { return hands_[static_cast<std::size_t>(hand)].mode != Mode::Open; }
  [[nodiscard]] bool holdingBase() const { return baseOffset_.has_value(); }
  [[nodiscard]] const InputSettings& settings() const { return settings_; }

 private:
  enum class Mode { Open, Pinch, Grip, Controller };
  struct HandState {
    Mode mode = Mode::Open;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    std::optional<interact::Twist> velocity;
  };
  void update(std::size_t k, const HandSample& sample);
  [[nodiscard]] Eigen::Isometry3d liftedBase(const Eigen::Isometry3d& pose) const;

  InputSettings settings_;
  std::optional<PartId> base_;
  Eigen::AlignedBox3d baseBox_;  // the base's own bounds
  double baseLowest_ = 0.0;      // its lowest point at load (world z)
  std::array<HandState, 2> hands_;
  bool leftOnPart_ = false;
  std::optional<Eigen::Isometry3d> baseOffset_;  // left hand -> base while it holds it
};

}  // namespace vaw::xr
