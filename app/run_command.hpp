#pragma once
#include <string>

namespace vaw::app {
// `vaw-sim run`: the options as parsed in vaw_sim.cpp; docs/inputs-format.md has the files.
struct RunArgs {
  std::string scene, inputs, out, replay;
};
int run(const RunArgs& args);
}  // namespace vaw::app
