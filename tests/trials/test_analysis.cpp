// The analysis recovers a simulated participant's known scale through every method, its 95 % intervals
// cover the truth 90-98 % of the time over 200 seeded participants, and the staircases converge.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "trials_test_support.hpp"

using namespace vaw::trials;
using vaw::trialtest::design;
using vaw::trialtest::simulate;

namespace {

constexpr double kTruePse = 0.3;
constexpr int kParticipants = 200;

ParticipantModel participant(std::uint64_t seed) {
  return {.pse = kTruePse, .sigmaLog = 0.25, .lapse = 0.02, .adjustSdLog = 0.2, .seed = seed};
}

Quest quest() {
  Quest q;
  q.trials = 60;
  q.priorScale = 0.5;
  q.range = {0.02, 3.0};
  return q;
}

Adjustment adjustment() {
  Adjustment a;
  a.trials = 10;
  a.range = {0.02, 3.0};
  return a;
}

struct Coverage {
  int covered = 0;
  int estimated = 0;
  double medianWidth = 0.0;  // hi / lo of the interval, median over participants
};

// Runs kParticipants seeded participants through the design and counts how often the interval holds
// the true scale. Participant and design seeds both vary, so orders and answers differ.
Coverage coverage(const Method& method, AnswerKind answers = AnswerKind::TooFastTooSlow) {
  Coverage c;
  std::vector<double> widths;
  for (int i = 0; i < kParticipants; ++i) {
    const auto seed = static_cast<std::uint64_t>(1000 + i);
    const auto results = analyze({simulate(design(method, seed, answers), participant(seed))});
    const ParticipantResult& p = results.at(0).participants.at(0);
    if (!p.estimate()) continue;
    ++c.estimated;
    c.covered += p.interval().contains(kTruePse) ? 1 : 0;
    widths.push_back(p.interval().hi / p.interval().lo);
  }
  std::sort(widths.begin(), widths.end());
  if (!widths.empty()) c.medianWidth = widths[widths.size() / 2];
  return c;
}

void expectCoverage(const char* method, const Coverage& c) {
  std::printf("[ info ] %s: %d of %d intervals cover the true PSE %.2f (%d estimated); median interval hi/lo %.3f\n", method,
              c.covered, kParticipants, kTruePse, c.estimated, c.medianWidth);
  EXPECT_EQ(c.estimated, kParticipants) << method << ": every participant gets an estimate";
  EXPECT_GE(c.covered, 180) << method << ": 95 % intervals cover at least 90 % of the time";
  EXPECT_LE(c.covered, 196) << method << ": and at most 98 %";
}

}  // namespace

TEST(Analysis, RecoversTheKnownScaleThroughEveryMethod) {
  const std::pair<const char*, Design> designs[] = {
      {"constant stimuli", design(vaw::trialtest::constantStimuli(10), 3)},
      {"staircase", design(vaw::trialtest::staircase(), 3)},
      {"quest", design(quest(), 3)},
      {"adjustment", design(adjustment(), 3)},
      {"two-interval constant stimuli", design(vaw::trialtest::constantStimuli(10), 3, AnswerKind::TwoInterval)},
  };
  for (const auto& [name, d] : designs) {
    const auto a = analyze({simulate(d, participant(3))});
    ASSERT_EQ(a.size(), 1u);
    const ParticipantResult& p = a[0].participants.at(0);
    ASSERT_TRUE(p.estimate()) << name;
    std::printf("[ info ] %s: estimate %.4f, interval [%.4f, %.4f], true %.2f\n", name, *p.estimate(), p.interval().lo,
                p.interval().hi, kTruePse);
    EXPECT_TRUE(p.interval().contains(kTruePse)) << name;
    EXPECT_LT(std::abs(std::log(*p.estimate() / kTruePse)), std::log(1.3)) << name << ": within 30 %";
  }
}

TEST(Analysis, ConstantStimuliIntervalsCover) { expectCoverage("constant stimuli, 70 trials", coverage(vaw::trialtest::constantStimuli(10))); }
TEST(Analysis, StaircaseIntervalsCover) { expectCoverage("staircase, <= 80 trials", coverage(vaw::trialtest::staircase())); }
TEST(Analysis, QuestIntervalsCover) { expectCoverage("quest, 60 trials", coverage(quest())); }
TEST(Analysis, AdjustmentIntervalsCover) { expectCoverage("adjustment, 10 settings", coverage(adjustment())); }

TEST(Analysis, StaircaseConvergesWithinFortyTrials) {
  // Converged: the fit of the first 40 trials (20 per staircase) lies within 25 % of the true PSE.
  // Stated number: 40 trials for at least 95 % of 200 participants.
  int converged = 0;
  Staircase s = vaw::trialtest::staircase();
  s.minTrials = s.maxTrials = 20;
  for (int i = 0; i < kParticipants; ++i) {
    const auto seed = static_cast<std::uint64_t>(5000 + i);
    const auto a = analyze({simulate(design(s, seed), participant(seed))});
    const auto est = a.at(0).participants.at(0).estimate();
    converged += est && std::abs(std::log(*est / kTruePse)) < std::log(1.25) ? 1 : 0;
  }
  std::printf("[ info ] staircase: %d of %d participants within 25 %% of the PSE after 40 trials\n", converged, kParticipants);
  EXPECT_GE(converged, 190);
}

TEST(Analysis, PooledEstimateIsTheParticipantsGeometricMeanWithAnInterval) {
  // Eight participants whose own PSEs differ: 0.2 ... 0.45.
  std::vector<ResultsFile> files;
  const double pses[] = {0.2, 0.24, 0.27, 0.3, 0.33, 0.36, 0.4, 0.45};
  double logSum = 0.0;
  for (int i = 0; i < 8; ++i) {
    Design d = design(vaw::trialtest::constantStimuli(10), static_cast<std::uint64_t>(40 + i));
    d.participant = "P" + std::to_string(i);
    ParticipantModel m = participant(static_cast<std::uint64_t>(40 + i));
    m.pse = pses[i];
    files.push_back(simulate(d, m));
    logSum += std::log(pses[i]);
  }
  const auto a = analyze(files);
  ASSERT_EQ(a.size(), 1u);
  ASSERT_EQ(a[0].participants.size(), 8u);
  ASSERT_TRUE(a[0].pooled);
  double estimatesLogSum = 0.0;
  for (const auto& p : a[0].participants) estimatesLogSum += std::log(*p.estimate());
  EXPECT_NEAR(a[0].pooled->estimate, std::exp(estimatesLogSum / 8.0), 1e-12);
  EXPECT_TRUE(a[0].pooled->interval.contains(std::exp(logSum / 8.0)));
  EXPECT_EQ(a[0].pooled->participants, 8);
  ASSERT_TRUE(a[0].allAnswersFit && a[0].allAnswersFit->ok);
  EXPECT_EQ(a[0].allAnswersFit->trials, 560);
}

TEST(Analysis, ConditionsAndParticipantsAreKeptApart) {
  Design drop = design(vaw::trialtest::constantStimuli(4), 1);
  Design gear = drop;
  gear.scenario = Scenario::GearPendulum;
  gear.motion = MotionKind::Rotation;
  Design dropAgain = design(vaw::trialtest::staircase(), 2);  // the same participant, another method
  drop.viewing = dropAgain.viewing = Viewing{{1.0, 1.0}, {}};
  const auto a = analyze({simulate(drop, participant(1)), simulate(gear, participant(2)), simulate(dropAgain, participant(3))});
  ASSERT_EQ(a.size(), 2u);
  EXPECT_EQ(a[0].participants.size(), 1u) << "one participant's two files are analysed together";
  EXPECT_EQ(a[0].participants[0].files.size(), 2u);
  EXPECT_EQ(a[0].participants[0].trials, 28 + static_cast<int>(simulate(dropAgain, participant(3)).records.size()));
  ASSERT_TRUE(a[0].predicted);
  EXPECT_EQ(a[0].predicted->recommendedScale, 1.0);
  EXPECT_FALSE(a[1].predicted) << "no viewing geometry for the gear";
}

TEST(Analysis, AnswersAllOneWayGiveNoEstimateAndSayWhy) {
  Design d = design(vaw::trialtest::constantStimuli(3), 1);
  Procedure p(d);
  while (p.next()) p.answer(Answer{Judgement::TooSlow, {}});
  const auto a = analyze({ResultsFile{"x", d, p.records(), std::nullopt}});
  EXPECT_FALSE(a[0].participants[0].estimate());
  EXPECT_FALSE(a[0].pooled);
  ASSERT_EQ(a[0].notes.size(), 1u);
  EXPECT_NE(a[0].notes[0].find("every answer \"slower\""), std::string::npos) << a[0].notes[0];
}

TEST(Analysis, PerfectlySeparatedAnswersGiveAnIntervalBetweenTheScales) {
  // "too slow" at 0.2 and below, "too fast" at 0.3 and above: the PSE lies between them.
  std::vector<Judged> data;
  for (double s : {0.1, 0.15, 0.2, 0.3, 0.45, 0.7})
    for (int i = 0; i < 5; ++i) data.push_back({s, s > 0.25});
  AnalysisOptions o;
  o.lapse = 0.0;
  const PsychometricFit f = fitPsychometric(data, o);
  ASSERT_TRUE(f.ok) << f.problem;
  EXPECT_GT(f.pse, 0.2);
  EXPECT_LT(f.pse, 0.3);
  // The interval spans the gap between the scales and stops short of them: at 0.2 itself half the
  // answers there would be "faster", which five "slower" answers make unlikely.
  EXPECT_GT(f.pseInterval.lo, 0.2);
  EXPECT_LT(f.pseInterval.lo, 0.21);
  EXPECT_LT(f.pseInterval.hi, 0.3);
  EXPECT_GT(f.pseInterval.hi, 0.29);
}

TEST(Analysis, SettingsEstimateMatchesHandComputation) {
  // ln settings: ln 0.2, ln 0.3, ln 0.45 -> mean ln 0.3 exactly; sd of (-ln 1.5, 0, ln 1.5) = ln 1.5.
  const SettingsEstimate e = estimateSettings({0.2, 0.3, 0.45});
  ASSERT_TRUE(e.ok);
  EXPECT_NEAR(e.geometricMean, 0.3, 1e-12);
  EXPECT_NEAR(e.sdLog, std::log(1.5), 1e-12);
  // t(0.975, 2) = 4.302653; half-width 4.302653 * ln 1.5 / sqrt 3.
  const double half = 4.302652730 * std::log(1.5) / std::sqrt(3.0);
  EXPECT_NEAR(e.meanInterval.lo, 0.3 * std::exp(-half), 1e-8);
  EXPECT_NEAR(e.meanInterval.hi, 0.3 * std::exp(half), 1e-8);
  EXPECT_EQ(e.median, 0.3);
  EXPECT_NEAR(e.medianCoverage, 0.75, 1e-12) << "three settings: [min, max] covers 1 - 2 / 8";
  EXPECT_FALSE(estimateSettings({0.3}).ok);
}

TEST(Analysis, StartPointBiasPullsAdjustmentsTowardTheStarts) {
  // Starts drawn from [0.6, 1.5], all above the preferred 0.3: a participant pulled halfway toward the
  // start sets well above 0.3, which is the method's known bias (and why starts are randomised widely).
  Adjustment a = adjustment();
  a.start = {0.6, 1.5};
  ParticipantModel m = participant(8);
  m.startPull = 0.5;
  const auto est = analyze({simulate(design(a, 8), m)}).at(0).participants.at(0).estimate();
  ASSERT_TRUE(est);
  EXPECT_GT(*est, 0.45);
}
