#pragma once
// The steps of a recording that a part's path is taken over, shared by its swept volume
// (docs/swept-volume.md) and its clearance (docs/clearance.md): the steps of a time span when one is
// given, else every step the part is carried (INHAND or ONTOOL).
#include <optional>
#include <string>

#include "vaw/assembly.hpp"
#include "vaw/sim/session.hpp"

namespace vaw::sim {

class World;

struct PathSpan {
  std::optional<double> from, to;  // s

  // Does the step `w` is at belong to the path of `part`.
  [[nodiscard]] bool holds(const World& w, PartId part) const;
  // Throws vaw::InputError naming `file`: the span held no step of the recording.
  [[noreturn]] void noStep(const std::string& file, const Assembly& a, PartId part) const;
};

// What an error about a recorded path names: the session's file, or its scene for one never saved.
std::string sessionName(const Session& s);

}  // namespace vaw::sim
