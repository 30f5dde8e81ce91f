#pragma once
// Estimates from answered trials: per participant and pooled, with intervals, next to the scale the
// head-demand model predicts (docs/trials.md, "Analysis").
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "vaw/human/head_demand.hpp"
#include "vaw/trials/results.hpp"

namespace vaw::trials {

// A confidence interval of a scale. An end the data do not bound is 0 (below) or +infinity (above).
struct Interval {
  double lo = 0.0;
  double hi = std::numeric_limits<double>::infinity();
  [[nodiscard]] bool contains(double x) const { return lo <= x && x <= hi; }
};

struct AnalysisOptions {
  double confidence = 0.95;
  // The lapse rate assumed in the psychometric fit: fixed, not fitted (docs/trials.md says why).
  double lapse = 0.02;
};

// One judgement: the trial's scale, and whether it was judged the faster (see judgedFaster).
struct Judged {
  double scale = 1.0;
  bool faster = false;
};

// Maximum-likelihood fit of P(faster) = lapse + (1 - 2 lapse) Phi((ln s - ln pse) / sigmaLog), with a
// profile-likelihood interval for the PSE.
struct PsychometricFit {
  bool ok = false;
  std::string problem;  // why there is no estimate, when !ok
  int trials = 0;
  double pse = 0.0;
  Interval pseInterval;
  double sigmaLog = 0.0;
  double lapse = 0.0;
  double logLikelihood = 0.0;
};

PsychometricFit fitPsychometric(const std::vector<Judged>& data, const AnalysisOptions& options = {});
double psychometric(double scale, double pse, double sigmaLog, double lapse);

// Method of adjustment: the geometric mean of the settings with a t interval on their logarithms, and
// the median with a distribution-free interval (order statistics) and that interval's exact coverage.
struct SettingsEstimate {
  bool ok = false;
  std::string problem;
  int settings = 0;
  double geometricMean = 0.0;
  Interval meanInterval;
  double sdLog = 0.0;
  double median = 0.0;
  Interval medianInterval;
  double medianCoverage = 0.0;
};

SettingsEstimate estimateSettings(const std::vector<double>& settings, const AnalysisOptions& options = {});

// Answers and objective measures at one scale (for adjustment, at the settings).
struct ScaleSummary {
  double scale = 0.0;
  int trials = 0;
  int faster = 0;
  int caught = 0;
  std::optional<double> medianRegrasp_s;
};

struct ParticipantResult {
  std::string participant;
  std::vector<std::string> files;
  std::vector<std::string> methods;
  int trials = 0;
  std::optional<PsychometricFit> fit;        // judgement answers
  std::optional<SettingsEstimate> settings;  // adjustment
  std::vector<double> reversalMeans;         // staircases: mean log scale at reversals after the first two, as a scale
  std::vector<ScaleSummary> perScale;
  int caught = 0;
  std::optional<double> medianRegrasp_s;
  // The participant's estimate (PSE or geometric mean of settings) and its interval, when there is one.
  [[nodiscard]] std::optional<double> estimate() const;
  [[nodiscard]] Interval interval() const;
};

// Across participants: the geometric mean of their estimates with a t interval on the logarithms (each
// participant one observation, so differences between people widen it); with one participant, that
// participant's estimate and interval.
struct Pooled {
  int participants = 0;
  double estimate = 0.0;
  Interval interval;
};

// Results that can be analysed together: the same scenario, motion, kind of answer and viewing geometry.
struct Condition {
  Scenario scenario = Scenario::DropFromHand;
  MotionKind motion = MotionKind::FreeFlight;
  AnswerKind answers = AnswerKind::TooFastTooSlow;
  std::optional<double> referenceScale;
  std::optional<Viewing> viewing;
};

struct ConditionAnalysis {
  Condition condition;
  std::vector<ParticipantResult> participants;
  std::optional<Pooled> pooled;
  std::optional<PsychometricFit> allAnswersFit;  // every judgement in one fit: the curve a chart draws
  std::vector<ScaleSummary> perScale;            // every participant's answers
  std::optional<human::ScaleRecommendation> predicted;  // the head-demand model, when viewing is given
  std::vector<std::string> notes;                // estimates left out of the pool, and why
};

// Groups the files by condition and, within one, by participant (files of one participant are
// analysed together), then estimates.
std::vector<ConditionAnalysis> analyze(const std::vector<ResultsFile>& files, const AnalysisOptions& options = {});

}  // namespace vaw::trials
