#include "vaw/interaction/states.hpp"

#include <cstdio>
#include <sstream>

namespace vaw::interact {

std::string_view name(PartState s) {
  switch (s) {
    case PartState::InHand: return "INHAND";
    case PartState::OnTool: return "ONTOOL";
    case PartState::OnBaseSlide: return "ONBASESLIDE";
    case PartState::OnBaseStatic: return "ONBASESTATIC";
    case PartState::InSpace: return "INSPACE";
    case PartState::Static: return "STATIC";
    case PartState::Placed: return "PLACED";
  }
  return "?";
}

std::string_view name(Event e) {
  switch (e) {
    case Event::Grab: return "grab";
    case Event::Release: return "release";
    case Event::ToolAttach: return "tool-attach";
    case Event::ToolDetach: return "tool-detach";
    case Event::ConstraintRecognized: return "constraint-recognized";
    case Event::StaticFrictionOvercome: return "static-friction-overcome";
    case Event::Stopped: return "stopped";
    case Event::Blocked: return "blocked";
    case Event::LostContact: return "lost-contact";
    case Event::HitEnvironment: return "hit-environment";
    case Event::ReachedFinalLocation: return "reached-final-location";
  }
  return "?";
}

std::string_view name(Guard g) {
  switch (g) {
    case Guard::None: return "";
    case Guard::CanGrab: return "category allows these hands";
    case Guard::Dynamic: return "one-hand part";
    case Guard::NotDynamic: return "two-hand or tool part";
    case Guard::PartnersPlaced: return "partners placed";
  }
  return "?";
}

std::string refusal(Guard g, const GuardContext& c) {
  switch (g) {
    case Guard::None: return {};
    case Guard::CanGrab:
      if (c.hands == Hands::None) return "no hand is grabbing";
      if (c.category == Category::Tool) return "a tool-lifted part can be lifted only by a tool";
      if (c.category == Category::TwoHand && c.hands != Hands::Both) return "a two-hand part needs both hands";
      return {};
    case Guard::Dynamic:
      return c.category == Category::OneHand ? std::string() : "only one-hand parts get dynamic simulation";
    case Guard::NotDynamic:
      return c.category != Category::OneHand ? std::string() : "a one-hand part is simulated";
    case Guard::PartnersPlaced:
      return c.unplacedPartner.empty() ? std::string() : "its partner " + c.unplacedPartner + " is not placed yet";
  }
  return "unknown guard";
}

const std::vector<Transition>& transitionTable() {
  using S = PartState;
  using E = Event;
  using G = Guard;
  static const std::vector<Transition> table{
      // Taking hold.
      {S::Static, E::Grab, G::CanGrab, S::InHand, "picked up"},
      {S::OnBaseStatic, E::Grab, G::CanGrab, S::InHand, "picked off the base"},
      {S::OnBaseSlide, E::Grab, G::CanGrab, S::InHand, "caught while sliding"},
      {S::InSpace, E::Grab, G::CanGrab, S::InHand, "caught in flight"},
      {S::Placed, E::Grab, G::CanGrab, S::InHand, "taken out of its assembled place"},
      {S::Static, E::ToolAttach, G::None, S::OnTool, "tool takes it"},
      {S::OnBaseStatic, E::ToolAttach, G::None, S::OnTool, "tool takes it off the base"},
      {S::Placed, E::ToolAttach, G::None, S::OnTool, "tool takes it out of its place"},
      // Letting go.
      {S::InHand, E::Release, G::Dynamic, S::InSpace, "thrown or dropped: free flight"},
      {S::InHand, E::Release, G::NotDynamic, S::Static, "set down where released (no dynamics)"},
      {S::OnTool, E::ToolDetach, G::None, S::Static, "set down by the tool"},
      {S::InHand, E::ConstraintRecognized, G::PartnersPlaced, S::OnBaseStatic, "released onto its mate"},
      {S::OnTool, E::ConstraintRecognized, G::PartnersPlaced, S::OnBaseStatic, "lowered onto its mate"},
      {S::InHand, E::ReachedFinalLocation, G::PartnersPlaced, S::Placed, "released at its assembled pose"},
      {S::OnTool, E::ReachedFinalLocation, G::PartnersPlaced, S::Placed, "lowered into its assembled pose"},
      // On the base.
      {S::OnBaseStatic, E::StaticFrictionOvercome, G::Dynamic, S::OnBaseSlide, "gravity beats static friction"},
      {S::OnBaseSlide, E::Stopped, G::None, S::OnBaseStatic, "kinetic friction stopped it"},
      {S::OnBaseSlide, E::Blocked, G::None, S::OnBaseStatic, "blocked by other geometry"},
      {S::OnBaseSlide, E::LostContact, G::None, S::InSpace, "slid off: free flight"},
      {S::OnBaseSlide, E::ReachedFinalLocation, G::PartnersPlaced, S::Placed, "slid into its assembled pose"},
      {S::OnBaseStatic, E::ReachedFinalLocation, G::PartnersPlaced, S::Placed, "resting at its assembled pose"},
      // In flight.
      {S::InSpace, E::HitEnvironment, G::None, S::Static, "hit the table or an object: stops (no resting pose)"},
  };
  return table;
}

Outcome fire(PartState from, Event e, const GuardContext& c) {
  Outcome out;
  std::string refusals;
  bool anyRow = false;
  for (const auto& t : transitionTable()) {
    if (t.from != from || t.event != e) continue;
    anyRow = true;
    const std::string why = refusal(t.guard, c);
    if (why.empty()) {
      out.accepted = true;
      out.to = t.to;
      return out;
    }
    refusals += (refusals.empty() ? "" : "; ") + why;
  }
  out.to = from;
  out.reason = anyRow ? refusals
                      : "no transition for " + std::string(name(e)) + " in state " + std::string(name(from));
  return out;
}

std::string tableText() {
  std::ostringstream s;
  char line[256];
  std::snprintf(line, sizeof line, "%-13s %-25s %-28s %-13s %s\n", "state", "event", "guard", "next", "meaning");
  s << line;
  for (const auto& t : transitionTable()) {
    std::snprintf(line, sizeof line, "%-13s %-25s %-28s %-13s %s\n", std::string(name(t.from)).c_str(),
                  std::string(name(t.event)).c_str(), std::string(name(t.guard)).c_str(), std::string(name(t.to)).c_str(),
                  std::string(t.why).c_str());
    s << line;
  }
  return s.str();
}

std::string tableDot() {
  std::ostringstream s;
  s << "// Generated by `vaw-sim states --dot` from vaw::interact::transitionTable(); do not edit.\n"
    << "digraph part_states {\n  rankdir=LR;\n  node [shape=box, style=rounded, fontname=\"Helvetica\"];\n"
    << "  edge [fontname=\"Helvetica\", fontsize=10];\n";
  for (PartState st : kAllStates) s << "  " << name(st) << ";\n";
  for (const auto& t : transitionTable()) {
    s << "  " << name(t.from) << " -> " << name(t.to) << " [label=\"" << name(t.event);
    if (t.guard != Guard::None) s << "\\n[" << name(t.guard) << "]";
    s << "\"];\n";
  }
  s << "}\n";
  return s.str();
}

}  // namespace vaw::interact
