// The designs the workbench bundles hold for the participants docs/trials.md says they are for: every
// simulated participant in that range gets an estimate or a reason, and the 95 % intervals hold the true
// scale 90-98 % of the time across the range, with no corner of it far off.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "bundled.hpp"
#include "trials_test_support.hpp"

using namespace vaw::trials;
using vaw::trialtest::simulate;

namespace {

constexpr int kRunsPerModel = 200;

// The range docs/trials.md states: a preferred scale from the source paper's 0.2 to full gravity (the
// scale a later study found most natural), answers from as sharp as the test participant's to twice as
// noisy, and up to one lapse in twenty.
std::vector<ParticipantModel> participantRange() {
  std::vector<ParticipantModel> models;
  for (const double pse : {0.2, 0.3, 0.45, 0.6, 1.0})
    for (const auto& [sigma, lapse] : {std::pair{0.25, 0.0}, std::pair{0.35, 0.02}, std::pair{0.5, 0.05}})
      models.push_back({.pse = pse, .sigmaLog = sigma, .lapse = lapse, .adjustSdLog = sigma});
  return models;
}

Design bundled(const std::string& name) { return loadDesign(vaw::test::resources() / "trials" / (name + ".vaw-trial.json")); }

struct ModelCoverage {
  int estimated = 0;
  int covered = 0;
  int reasoned = 0;  // no estimate, and a note saying why
};

ModelCoverage coverage(const Design& design, ParticipantModel model) {
  ModelCoverage c;
  for (int i = 0; i < kRunsPerModel; ++i) {
    Design d = design;
    d.seed = design.seed + static_cast<std::uint64_t>(i);
    model.seed = 1000 + static_cast<std::uint64_t>(i);
    const auto a = analyze({simulate(d, model)});
    const ParticipantResult& p = a.at(0).participants.at(0);
    if (p.estimate()) {
      ++c.estimated;
      c.covered += p.interval().contains(model.pse) ? 1 : 0;
    } else if (a[0].notes.size() == 1 && a[0].notes[0].find("no estimate: ") != std::string::npos) {
      ++c.reasoned;
    }
  }
  return c;
}

void expectHoldsForTheRange(const std::string& name) {
  const Design design = bundled(name);
  int estimated = 0, covered = 0;
  double lowest = 1.0, highest = 0.0;
  for (const ParticipantModel& m : participantRange()) {
    const ModelCoverage c = coverage(design, m);
    EXPECT_EQ(c.estimated + c.reasoned, kRunsPerModel)
        << name << ", pse " << m.pse << ", sigma " << m.sigmaLog << ": every participant gets an estimate or a reason";
    EXPECT_GE(c.estimated, kRunsPerModel * 97 / 100) << name << ", pse " << m.pse << ", sigma " << m.sigmaLog;
    const double share = static_cast<double>(c.covered) / c.estimated;
    std::printf("[ info ] %s: pse %.2f, sigma %.2f, lapse %.2f: %d estimates, %d reasons, %.1f %% covered\n", name.c_str(), m.pse,
                m.sigmaLog, m.lapse, c.estimated, c.reasoned, 100.0 * share);
    // With 200 runs a model's share scatters by about 2 points around its true coverage; 87 % and 99 %
    // are where a true 90 % or 98 % would rarely reach.
    EXPECT_GE(share, 0.87) << name << ", pse " << m.pse << ", sigma " << m.sigmaLog << ", lapse " << m.lapse;
    EXPECT_LE(share, 0.99) << name << ", pse " << m.pse << ", sigma " << m.sigmaLog << ", lapse " << m.lapse;
    lowest = std::min(lowest, share);
    highest = std::max(highest, share);
    estimated += c.estimated;
    covered += c.covered;
  }
  const double share = static_cast<double>(covered) / estimated;
  std::printf("[ info ] %s: %.1f %% of %d intervals across the range hold the true scale (per model %.1f-%.1f %%)\n", name.c_str(),
              100.0 * share, estimated, 100.0 * lowest, 100.0 * highest);
  EXPECT_GE(share, 0.90) << name;
  EXPECT_LE(share, 0.98) << name;
}

}  // namespace

TEST(BundledDesigns, DropConstantStimuliHoldsAcrossTheParticipantRange) { expectHoldsForTheRange("drop-constant-stimuli"); }
TEST(BundledDesigns, ThrowStaircaseHoldsAcrossTheParticipantRange) { expectHoldsForTheRange("throw-staircase"); }
TEST(BundledDesigns, SlideTwoIntervalHoldsAcrossTheParticipantRange) { expectHoldsForTheRange("slide-two-interval"); }
TEST(BundledDesigns, GearAdjustmentHoldsAcrossTheParticipantRange) { expectHoldsForTheRange("gear-adjustment"); }

TEST(BundledDesigns, ATwoIntervalSessionWithoutAnEstimateSaysWhyInTheQuestionsTerms) {
  // Scales that all lie above the participant's match for the reference: every trial's fall is judged
  // the faster, which is what the bundled slide design gave four participants in five before its scales
  // were widened.
  Design d = bundled("slide-two-interval");
  auto& c = std::get<ConstantStimuli>(d.method);
  c.scales = {0.5, 0.7, 0.85, 1.0, 1.2, 1.4};
  c.repetitions = 3;
  const ParticipantModel sharp{.pse = 0.25, .sigmaLog = 0.1, .lapse = 0.0, .seed = 3};
  const auto a = analyze({simulate(d, sharp)});
  EXPECT_FALSE(a.at(0).participants.at(0).estimate());
  ASSERT_EQ(a[0].notes.size(), 1u);
  const std::string& note = a[0].notes[0];
  EXPECT_NE(note.find("every answer \"faster\": the PSE lies below 0.5, the lowest scale tested: add lower scales"), std::string::npos)
      << note;
  EXPECT_NE(note.find("reference, scale 1, was judged the faster"), std::string::npos) << note;
}
