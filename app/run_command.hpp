#pragma once
#include <string>
#include <vector>

namespace vaw::app {
// `vaw-sim run`: see the usage text in vaw_sim.cpp and docs/inputs-format.md.
int run(const std::vector<std::string>& args);
}
