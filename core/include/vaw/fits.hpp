#pragma once
// What a shaft larger than its bore is by design (docs/step.md, "Fits as designers model them"): CAD users
// model a tapped hole at its tap-drill diameter and the screw at its nominal one (the cosmetic-thread
// convention: an M6 screw's 6 mm shank in a 5 mm hole), and a press fit with a few micrometres of
// interference. Either is a fit, not a clash.
#include <optional>
#include <string>

#include "vaw/assembly.hpp"

namespace vaw {

struct DesignedInterference {
  Constraint::Found::Fit fit = Constraint::Found::Fit::Threaded;  // Threaded or Press
  std::string thread;  // Threaded: the size, "M6" or "1/4-20 UNC"
};

// Threaded when the shaft's diameter is a thread's nominal diameter (ISO metric coarse and fine, UNC and
// UNF) and the bore's lies between that thread's minor diameter and its nominal diameter less 0.4 of its
// pitch (a tap drill, or a hole at the minor diameter, with a modelling allowance); press when the
// interference is at most 1 % of the shaft's radius; otherwise none (a clash). Radii in metres, the
// shaft's larger than the bore's.
std::optional<DesignedInterference> designedInterference(double shaftRadius, double boreRadius);

// "M6", "1/4-20 UNC" and the pitch (m) of the thread of that nominal diameter, when there is one.
struct ThreadSize {
  const char* name;
  double major;  // nominal (major) diameter, m
  double pitch;  // m
};
std::optional<ThreadSize> threadOfDiameter(double diameter);

}  // namespace vaw
