// The methods' trial sequences: blocked and blinded constant stimuli, staircase rules, adjustment
// starts, two-interval order, and refused answers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "trials_test_support.hpp"

using namespace vaw::trials;
using vaw::trialtest::design;

namespace {

Answer judgement(Judgement j) { return Answer{j, {}}; }

std::vector<double> scalesOf(const Procedure& p) {
  std::vector<double> s;
  for (const auto& r : p.records()) s.push_back(r.trial.scale);
  return s;
}

}  // namespace

TEST(Procedure, ConstantStimuliShowsEveryScaleOncePerBlockInASeededOrder) {
  const auto cs = vaw::trialtest::constantStimuli(6);
  Procedure p(design(cs, 11));
  EXPECT_EQ(p.plannedTrials(), 42);
  while (p.next()) {
    EXPECT_TRUE(p.next()->blinded);
    EXPECT_FALSE(p.next()->staircase);
    p.answer(judgement(Judgement::TooSlow));
  }
  const auto order = scalesOf(p);
  ASSERT_EQ(order.size(), 42u);
  for (std::size_t block = 0; block < 6; ++block) {
    std::vector<double> b(order.begin() + static_cast<long>(7 * block), order.begin() + static_cast<long>(7 * block + 7));
    std::sort(b.begin(), b.end());
    EXPECT_EQ(b, cs.scales) << "block " << block;
  }
  // The order is shuffled (not the listed order), the same for the same seed, different for another.
  EXPECT_NE(std::vector<double>(order.begin(), order.begin() + 7), cs.scales);
  Procedure same(design(cs, 11)), other(design(cs, 12));
  while (same.next()) same.answer(judgement(Judgement::TooFast));
  while (other.next()) other.answer(judgement(Judgement::TooFast));
  EXPECT_EQ(scalesOf(same), order) << "answers do not change a constant-stimuli order";
  EXPECT_NE(scalesOf(other), order);
}

TEST(Procedure, StaircaseStepsDownOnTooFastUpOnTooSlowAndShrinksStepsAtReversals) {
  Staircase s = vaw::trialtest::staircase();
  s.stepFactors = {2.0, 1.5};
  s.minTrials = s.maxTrials = 5;
  Procedure p(design(s));
  // Answer "too fast" above 0.31, "too slow" below (0.31, not 0.3: the descending staircase lands on 0.3
  // up to rounding).
  std::map<int, std::vector<double>> seen;
  while (p.next()) {
    seen[*p.next()->staircase].push_back(p.next()->scale);
    p.answer(judgement(p.next()->scale > 0.31 ? Judgement::TooFast : Judgement::TooSlow));
  }
  ASSERT_EQ(seen.size(), 2u);
  // Ascending from 0.08: x2 to 0.16, 0.32; then down: a reversal, so /1.5: 0.2133; up again x1.5: 0.32.
  const std::vector<double> up{0.08, 0.16, 0.32, 0.32 / 1.5, 0.32};
  // Descending from 1.2: /2 to 0.6, 0.3; up (reversal) x1.5: 0.45; down (reversal) /1.5: 0.3.
  const std::vector<double> down{1.2, 0.6, 0.3, 0.45, 0.3};
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_NEAR(seen[0][i], up[i], 1e-12) << i;
    EXPECT_NEAR(seen[1][i], down[i], 1e-12) << i;
  }
  // Every change of direction is a reversal, at the scale where it turned.
  const std::vector<double> upTurns{0.32, 0.32 / 1.5, 0.32}, downTurns{0.3, 0.45, 0.3};
  for (std::size_t k = 0; k < 2; ++k) {
    ASSERT_EQ(p.reversals()[k].size(), 3u);
    for (std::size_t i = 0; i < 3; ++i) EXPECT_NEAR(p.reversals()[k][i], (k == 0 ? upTurns : downTurns)[i], 1e-12);
  }
  EXPECT_EQ(p.records().size(), 10u);
}

TEST(Procedure, StaircasesInterleaveInSeededRounds) {
  Procedure p(design(vaw::trialtest::staircase(), 3));
  std::vector<int> who;
  while (p.next()) {
    who.push_back(*p.next()->staircase);
    p.answer(judgement(p.records().size() % 3 ? Judgement::TooFast : Judgement::TooSlow));
  }
  // Every round asks both staircases once while both run.
  int orderChanges = 0;
  for (std::size_t r = 0; r + 1 < who.size() && r + 1 < 60; r += 2) {
    EXPECT_NE(who[r], who[r + 1]) << "round " << r / 2;
    orderChanges += who[r] == 0 ? 1 : 0;
  }
  EXPECT_GT(orderChanges, 5) << "the ascending staircase is not always first";
  EXPECT_LT(orderChanges, 25) << "nor always second";
  EXPECT_LE(p.records().size(), 80u);
}

TEST(Procedure, StaircaseEndsAtMinimumTrialsAndReversalsOrAtTheMaximum) {
  Staircase s = vaw::trialtest::staircase();
  s.minTrials = 4;
  s.minReversals = 100;  // never reached: each staircase stops at maxTrials
  s.maxTrials = 9;
  Procedure p(design(s));
  while (p.next()) p.answer(judgement(p.next()->scale > 0.3 ? Judgement::TooFast : Judgement::TooSlow));
  EXPECT_EQ(p.records().size(), 18u);
  EXPECT_EQ(p.plannedTrials(), 18);
  s.minReversals = 2;
  Procedure q(design(s));
  while (q.next()) q.answer(judgement(q.next()->scale > 0.3 ? Judgement::TooFast : Judgement::TooSlow));
  EXPECT_LT(q.records().size(), 18u);
  for (const auto& r : q.reversals()) EXPECT_GE(r.size(), 2u);
}

TEST(Procedure, AdjustmentStartsAreLogUniformInTheStartRange) {
  Adjustment a;
  a.trials = 400;
  a.start = {0.1, 1.6};
  Procedure p(design(a));
  int below = 0;
  while (p.next()) {
    const Trial& t = *p.next();
    ASSERT_TRUE(t.adjustable);
    EXPECT_GE(t.scale, 0.1);
    EXPECT_LE(t.scale, 1.6);
    below += t.scale < 0.4 ? 1 : 0;  // the log midpoint of [0.1, 1.6]
    p.answer(Answer{Setting{0.3}, {}});
  }
  // Half below the log midpoint: 200 +- 3 sd (sd = 10).
  EXPECT_NEAR(below, 200, 30);
}

TEST(Procedure, TwoIntervalOrderIsRandomAndTheTrialsScaleIsJudged) {
  Procedure p(design(vaw::trialtest::constantStimuli(), 5, AnswerKind::TwoInterval));
  int referenceFirst = 0;
  while (p.next()) {
    ASSERT_TRUE(p.next()->referenceScale);
    EXPECT_EQ(*p.next()->referenceScale, 0.5);
    referenceFirst += p.next()->referenceFirst ? 1 : 0;
    // Always pick the interval that is not the reference: the trial's own fall judged faster.
    p.answer(judgement(p.next()->referenceFirst ? Judgement::Second : Judgement::First));
  }
  EXPECT_NEAR(referenceFirst, 35, 15);
  for (const auto& r : p.records()) EXPECT_TRUE(judgedFaster(r));
}

TEST(Procedure, AnswersThatDoNotFitAreRefusedAndChangeNothing) {
  Procedure cs(design(vaw::trialtest::constantStimuli(1)));
  EXPECT_THROW(cs.answer(Answer{Setting{0.3}, {}}), std::invalid_argument);
  EXPECT_THROW(cs.answer(judgement(Judgement::First)), std::invalid_argument);
  EXPECT_THROW(cs.answer(Answer{Judgement::TooFast, {true, -0.1}}), std::invalid_argument);
  EXPECT_TRUE(cs.records().empty());
  Procedure adj(design(Adjustment{}));
  EXPECT_THROW(adj.answer(Answer{Setting{5.0}, {}}), std::invalid_argument) << "outside the adjustable range";
  EXPECT_THROW(adj.answer(judgement(Judgement::TooFast)), std::invalid_argument);
  while (cs.next()) cs.answer(judgement(Judgement::TooFast));
  EXPECT_THROW(cs.answer(judgement(Judgement::TooFast)), std::invalid_argument) << "the session is complete";
}

TEST(Procedure, QuestPlacesTrialsAroundThePse) {
  Quest q;
  q.trials = 60;
  q.priorScale = 0.8;
  q.sigmaLog = 0.3;
  const ParticipantModel m{.pse = 0.25, .sigmaLog = 0.2, .seed = 4};
  Procedure p(design(q));
  while (p.next()) p.answer(simulateAnswer(m, *p.next()));
  // The last 20 trials lie at the posterior mean or one assumed spread (0.3 in ln scale) either side
  // of it; the mean by then is within 15 % of the participant's PSE.
  int below = 0, above = 0;
  for (std::size_t i = 40; i < 60; ++i) {
    const double x = std::log(p.records()[i].trial.scale / 0.25);
    EXPECT_LT(std::min({std::abs(x + 0.3), std::abs(x), std::abs(x - 0.3)}), std::log(1.15)) << i;
    below += x < -0.15 ? 1 : 0;
    above += x > 0.15 ? 1 : 0;
  }
  EXPECT_GT(below, 2);
  EXPECT_GT(above, 2);
}
