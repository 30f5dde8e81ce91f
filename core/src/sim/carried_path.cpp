#include "vaw/sim/carried_path.hpp"

#include <limits>

#include "vaw/error.hpp"
#include "vaw/sim/world.hpp"

namespace vaw::sim {

bool PathSpan::holds(const World& w, PartId part) const {
  if (from || to) {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    return w.time() >= from.value_or(-kInf) && w.time() <= to.value_or(kInf);
  }
  const interact::PartState s = w.part(part).state;
  return s == interact::PartState::InHand || s == interact::PartState::OnTool;
}

void PathSpan::noStep(const std::string& file, const Assembly& a, PartId part) const {
  if (from || to) fail(file, "from/to", "a span that holds steps of the recording", "no step in it");
  fail(file, "part", "a part carried (INHAND or ONTOOL) at some step", a.parts[part].name + " is never carried");
}

std::string sessionName(const Session& s) { return s.file.empty() ? s.scene : s.file.string(); }

}  // namespace vaw::sim
