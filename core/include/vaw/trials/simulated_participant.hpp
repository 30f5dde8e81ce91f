#pragma once
// A participant whose answers are drawn from a known psychometric curve, for testing the methods and
// for planning how many trials a study needs (`vaw-sim trials simulate`).
#include <cstdint>
#include <filesystem>

#include "vaw/trials/trial.hpp"

namespace vaw::trials {

struct ParticipantModel {
  // P("faster") = lapse + (1 - 2 lapse) Phi((ln scale - ln pse) / sigmaLog): "too fast" for one fall,
  // the trial's fall for two intervals (then pse is the scale that looks as fast as the reference).
  double pse = 0.3;
  double sigmaLog = 0.25;
  double lapse = 0.0;
  // Adjustment: ln setting = (1 - startPull) (ln pse + N(0, adjustSdLog)) + startPull ln start; a
  // startPull above 0 is the start-point bias of the method of adjustment.
  double adjustSdLog = 0.15;
  double startPull = 0.0;
  // Objective measures: P(caught) = Phi((ln catchScale - ln scale) / catchSigmaLog); a caught part is
  // back in hand after a log-normal time with median regraspMedian_s.
  double catchScale = 0.5;
  double catchSigmaLog = 0.3;
  double regraspMedian_s = 0.6;
  double regraspSdLog = 0.2;
  std::uint64_t seed = 1;
};

// Reads {"format": "vaw-simulated-participant", "version": 1, ...} (docs/trials.md); errors name the
// file and field.
ParticipantModel loadParticipantModel(const std::filesystem::path& file);

double probabilityFaster(const ParticipantModel& m, double scale);

// The answer to one trial. Its randomness depends only on the model's seed and the trial's index, so a
// session that is killed and resumed gets exactly the answers an uninterrupted one gets.
Answer simulateAnswer(const ParticipantModel& m, const Trial& trial);

}  // namespace vaw::trials
