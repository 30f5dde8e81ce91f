#pragma once
#include <string>
#include <vector>

#include "vaw/importer.hpp"

namespace vaw::app {
// `vaw-sim evaluate`: the options as parsed in vaw_sim.cpp; docs/evaluation.md has the output.
struct EvaluateArgs {
  std::string file;
  bool json = false;
  std::vector<std::string> sessions;  // recorded sessions of this assembly (participants)
  std::string report;                 // folder for report.html and its CSV and JSON
  std::string up;                     // CAD files: which way the assembly stands ("auto", "+y", ...)
  ImportOptions import;               // STEP files: the reader's limits (docs/step.md, "Limits")
};
// The exit status of `evaluate` when the assembly loaded and was searched but some part has no order.
inline constexpr int kExitNoOrder = 3;
int evaluate(const EvaluateArgs& args);
}  // namespace vaw::app
