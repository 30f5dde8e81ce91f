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
  bool ways = false;                  // each way home's clearance and swept volume (docs/evaluation.md)
  double thresholdMm = 5.0;           // with ways: closer than this to a part already in is a near miss
  double voxelMm = 1.0;               // with ways: the swept volumes' voxel
};
// The exit status of `evaluate` when the assembly loaded and was searched but some part has no order.
inline constexpr int kExitNoOrder = 3;
int evaluate(const EvaluateArgs& args);
}  // namespace vaw::app
