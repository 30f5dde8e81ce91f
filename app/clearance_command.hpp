#pragma once
#include <optional>
#include <string>

#include "vaw/importer.hpp"

namespace vaw::app {
// `vaw-sim clearance SESSION --part NAME --out DIR`: the options as parsed in vaw_sim.cpp (docs/clearance.md).
struct ClearanceArgs {
  std::string session, part, out;
  std::optional<double> from, to;  // s
  double thresholdMm = 5.0, reachMm = 50.0;
};
int clearance(const ClearanceArgs& args);

// `vaw-sim sweep SESSION --part NAME --out DIR`: the swept volume of the part's path and its clearance
// (docs/swept-volume.md).
struct SweepArgs {
  ClearanceArgs clearance;
  double voxelMm = 1.0;
  bool relativeToBase = false;
  ExportOptions step;  // the STEP writer's time and memory limits
};
int sweep(const SweepArgs& args);
}  // namespace vaw::app
