#pragma once
#include <optional>
#include <string>
#include <vector>

namespace vaw::app {
// `vaw-sim trials simulate|analyze|demand`: the options as parsed in vaw_sim.cpp; docs/trials.md.
struct TrialsSimulateArgs {
  std::string design, participant, out;
  int runs = 1;
  bool json = false;
};
struct TrialsAnalyzeArgs {
  std::vector<std::string> files;
  std::string png;
  std::optional<double> lapse;
  bool json = false;
};
struct TrialsDemandArgs {
  double distance = 0.0, height = 0.0;
  std::optional<double> pitchLimit, yawLimit, accelerationLimit;
  bool yaw = false;
};
int trialsSimulate(const TrialsSimulateArgs& args);
int trialsAnalyze(const TrialsAnalyzeArgs& args, int argc, char** argv);  // argc/argv: for the chart's Qt application
int trialsDemand(const TrialsDemandArgs& args);
}  // namespace vaw::app
