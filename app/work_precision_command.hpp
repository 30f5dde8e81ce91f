#pragma once
#include <string>
#include <vector>

namespace vaw::app {
// `vaw-sim work-precision`: see the usage text in vaw_sim.cpp.
int workPrecision(const std::vector<std::string>& args, int argc, char** argv);
}
