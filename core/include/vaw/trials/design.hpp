#pragma once
// A gravity-scale trial design: what is shown, which scale varies, how scales are chosen, what is
// asked. Loaded from a versioned JSON file (docs/trials.md has the format and a complete example).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "vaw/human/head_demand.hpp"

namespace vaw::trials {

inline constexpr int kDesignFormatVersion = 1;

enum class Scenario { DropFromHand, Throw, SlideOffTiltedBase, GearPendulum };
enum class MotionKind { FreeFlight, Slide, Rotation };
// TooFastTooSlow: one fall, "too fast" or "too slow". TwoInterval: two falls, the reference scale and
// the trial's, in random order; "which was faster". Setting: the participant adjusts the scale.
enum class AnswerKind { TooFastTooSlow, TwoInterval, Setting };

std::string_view name(Scenario s);
std::string_view name(MotionKind m);
std::string_view name(AnswerKind a);

struct ScaleRange {
  double min = 0.05;
  double max = 2.0;
};

// The participant sets the scale, starting from a value drawn log-uniformly from `start` each trial.
struct Adjustment {
  int trials = 10;
  ScaleRange range;
  ScaleRange start{0.1, 1.5};
};

// Every scale `repetitions` times; each repetition is one shuffled block, so every scale is shown once
// before any is shown again.
struct ConstantStimuli {
  std::vector<double> scales;
  int repetitions = 8;
};

// Two interleaved staircases, one from startLow and one from startHigh (PsychoPy's StairHandler,
// interleaved as its MultiStairHandler does): nDown "too fast" answers in a row lower the scale, nUp
// "too slow" answers raise it, by stepFactors[k] after k reversals (the last factor from then on). A
// staircase ends after minTrials trials and minReversals reversals, or at maxTrials.
struct Staircase {
  double startLow = 0.1;
  double startHigh = 1.5;
  std::vector<double> stepFactors{2.0, 1.5, 1.25};
  int nUp = 1;
  int nDown = 1;
  int minTrials = 20;
  int minReversals = 6;
  int maxTrials = 40;
  ScaleRange range;
};

// QUEST-like: a posterior over the log PSE on a grid, each trial at its mean (King-Smith et al. 1994),
// with an assumed spread and lapse for the update.
struct Quest {
  int trials = 40;
  double priorScale = 0.5;
  double priorSdLog = 1.0;
  double sigmaLog = 0.3;
  double lapse = 0.02;
  ScaleRange range;
};

using Method = std::variant<Adjustment, ConstantStimuli, Staircase, Quest>;
std::string_view methodName(const Method& m);

struct Question {
  std::string text;
  AnswerKind answers = AnswerKind::TooFastTooSlow;
  double referenceScale = 1.0;  // TwoInterval only
};

// The viewing geometry the demand model predicts a scale for; absent for motions a head need not follow.
struct Viewing {
  human::ViewingGeometry geometry;
  human::HeadLimits limits;
};

struct Design {
  std::string name;
  std::string participant;
  std::uint64_t seed = 0;
  Scenario scenario = Scenario::DropFromHand;
  MotionKind motion = MotionKind::FreeFlight;
  bool blind = true;  // the scale is never shown to the participant
  Question question;
  Method method;
  std::optional<Viewing> viewing;
};

// Throws vaw::InputError naming the file, the field and what was expected.
Design loadDesign(const std::filesystem::path& file);
// Canonical JSON, every field written: what loadDesign reads back as the same design.
std::string toJson(const Design& d);

}  // namespace vaw::trials
