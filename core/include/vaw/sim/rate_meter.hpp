#pragma once
// How fast simulated time really advances against the wall clock, over the last few seconds, and how much
// of that wall time the stepping itself took. The workbench paces the world by a timer (or the headset's
// frame loop) and drops time it cannot catch up on, so the speed it was asked for is not the speed it
// runs at when the machine is too slow; this says the real one, and whether the physics or everything
// else (drawing, above all) is what holds it back (docs/simulation.md, "When the simulation falls behind").
#include <deque>
#include <optional>

namespace vaw::sim {

class RateMeter {
 public:
  explicit RateMeter(double windowSeconds = 2.0) : window_(windowSeconds) {}

  // Forget the past: after a pause, a seek, a new speed or a new world.
  void reset() { samples_.clear(); }
  // After each batch of steps (or none): the wall clock (s, any origin), the simulated time (s) and the
  // wall time spent stepping since the previous sample (s).
  void sample(double wall, double simTime, double stepping);

  struct Reading {
    double rate = 1.0;           // simulated seconds per wall second
    double steppingShare = 0.0;  // fraction of the wall time spent stepping
  };
  // None until the samples span half the window.
  [[nodiscard]] std::optional<Reading> reading() const;

 private:
  struct Sample {
    double wall, simTime, steppingTotal;
  };
  double window_;
  double steppingTotal_ = 0.0;
  std::deque<Sample> samples_;
};

// Whether a measured rate is behind the speed asked for, with hysteresis so the verdict does not flicker:
// behind below 95 % of it, caught up again above 98 %.
[[nodiscard]] bool fallingBehind(const RateMeter::Reading& r, double speed, bool wasBehind);

}  // namespace vaw::sim
