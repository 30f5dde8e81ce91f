#pragma once
#include <string>
#include <vector>

namespace vaw::app {
// The STEP reader's limits, as `inspect` and `evaluate` take them (docs/step.md, "Limits").
struct ReaderLimits {
  double timeoutSeconds = 300.0;
  double memoryMB = 0.0;  // 0: half the machine's memory
  double maxInstances = 10000;
};
// `vaw-sim evaluate`: the options as parsed in vaw_sim.cpp; docs/evaluation.md has the output.
struct EvaluateArgs {
  std::string file;
  bool json = false;
  std::vector<std::string> sessions;  // recorded sessions of this assembly (participants)
  std::string report;                 // folder for report.html and its CSV and JSON
  std::string up;                     // CAD files: which way the assembly stands ("auto", "+y", ...)
  ReaderLimits reader;
};
// The exit status of `evaluate` when the assembly loaded and was searched but some part has no order.
inline constexpr int kExitNoOrder = 3;
int evaluate(const EvaluateArgs& args);
}  // namespace vaw::app
