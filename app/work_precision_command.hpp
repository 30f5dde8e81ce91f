#pragma once
#include <filesystem>

namespace vaw::app {
// `vaw-sim work-precision`: the options as parsed in vaw_sim.cpp; docs/work-precision.md has the output.
struct WorkPrecisionArgs {
  std::filesystem::path out;
  int repeats = 5;
  bool peers = true;
};
// argc/argv reach the Qt application that draws the charts.
int workPrecision(const WorkPrecisionArgs& args, int argc, char** argv);
}  // namespace vaw::app
