#pragma once
#include <string>

namespace vaw::app {
// `vaw-sim evaluate`: the options as parsed in vaw_sim.cpp; docs/evaluation.md has the output.
struct EvaluateArgs {
  std::string file;
  bool json = false;
};
int evaluate(const EvaluateArgs& args);
}  // namespace vaw::app
