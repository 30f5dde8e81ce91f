#pragma once
// A handling and insertion time estimate from the part itself, in the form of the Boothroyd-Dewhurst
// design-for-assembly method for manual assembly (G. Boothroyd, P. Dewhurst, W. A. Knight, "Product Design
// for Manufacture and Assembly", 3rd ed., CRC Press 2011, chapter 3; docs/evaluation.md has the rows used):
// a two-digit handling code from the part's symmetry about its insertion axis (alpha) and across it
// (beta), its size and thickness, and a two-digit insertion code from how it goes in. Next to a part's
// measured time it tells a part that is slow by design from one that was slow by accident.
#include <Eigen/Geometry>
#include <optional>
#include <string>

#include "vaw/assembly.hpp"

namespace vaw::eval {

struct DfaEstimate {
  double alpha_deg = 360.0;  // the smallest turn about the insertion axis that leaves the part looking the same
  double beta_deg = 360.0;   // the same for a turn about an axis across it (180: either end may go first)
  double size_m = 0.0;       // longest side of the part's principal box
  double thickness_m = 0.0;  // shortest side
  double mass_kg = 0.0;
  std::string handlingCode, insertionCode;
  double handling_s = 0.0, insertion_s = 0.0;
  // The chart's one-hand rows only: a two-hand or tool-lifted part gets them too, flagged as a lower bound.
  bool lowerBound = false;
  std::string why;  // one line: how each digit was chosen
  [[nodiscard]] double total_s() const { return handling_s + insertion_s; }
};

// `outAxis`: the part's way home reversed (world, unit), from the sequence plan; `how`: the constraint it
// comes home by (an insert's recognised clearance decides alignment and resistance), or none.
DfaEstimate estimateDfa(const Assembly& assembly, PartId part, const Eigen::Vector3d& outAxis, const Constraint* how);

}  // namespace vaw::eval
