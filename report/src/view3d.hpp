#pragma once
// The report's 3D view of the order (private to the report).
#include <string>

#include "vaw/assembly.hpp"
#include "vaw/evaluation/sequence.hpp"

namespace vaw::report {

// The section of report.html that plays the order in 3D, three.js and the order's glTF inlined; where
// three.js is not installed, a line that says so.
std::string orderView(const Assembly& a, const eval::SequencePlan& plan);

}  // namespace vaw::report
