#pragma once
// One trial as the runner asks for it, the participant's answer with its objective measures, and the
// record of both that the results file keeps.
#include <optional>
#include <string_view>
#include <variant>

#include "vaw/trials/design.hpp"

namespace vaw::trials {

struct Trial {
  int index = 0;  // 0-based position in the session
  Scenario scenario = Scenario::DropFromHand;
  MotionKind motion = MotionKind::FreeFlight;
  // The gravity scale to play for `motion`; for adjustment, the start value the participant adjusts from.
  double scale = 1.0;
  bool blinded = true;  // never show `scale` (or the reference) to the participant
  std::optional<int> staircase;                  // which interleaved staircase asks (staircase method)
  std::optional<double> referenceScale;          // two-interval: the other fall's scale ...
  bool referenceFirst = false;                   // ... and whether it plays first
  std::optional<ScaleRange> adjustable;          // adjustment: the range the participant may set
};

enum class Judgement { TooFast, TooSlow, First, Second };
std::string_view name(Judgement j);

// What the participant set, in the method of adjustment.
struct Setting {
  double scale = 1.0;
};

// Measured, not asked: whether the part was caught, and the time from its release until a hand held
// it again (absent when it was not taken back).
struct Measures {
  bool caught = false;
  std::optional<double> regraspTime_s;
};

struct Answer {
  std::variant<Judgement, Setting> response;
  Measures measures;
};

struct Record {
  Trial trial;
  Answer answer;
};

// Whether the participant judged the trial's own scale the faster one: "too fast", or in two-interval
// trials the interval that was not the reference. Undefined for settings.
bool judgedFaster(const Record& r);

}  // namespace vaw::trials
