#pragma once
#include <string>
#include <vector>

namespace vaw::app {
// `vaw-sim trials simulate|analyze|demand`: see the usage text in trials_command.cpp and docs/trials.md.
int trials(const std::vector<std::string>& args, int argc, char** argv);
}
