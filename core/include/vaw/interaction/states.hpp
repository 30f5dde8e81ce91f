#pragma once
// Part states and the transitions between them (docs/physics.md, "Part states"; the paper's figure 6 is lost).
// One table of (state, event, guard) -> state is the single source of truth: the world fires events
// through it, `vaw-sim states` prints it, and docs/states.dot is generated from it. An event with no
// row, or whose guard refuses, returns the reason; nothing is silently ignored.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "vaw/categories.hpp"

namespace vaw::interact {

enum class PartState { InHand, OnTool, OnBaseSlide, OnBaseStatic, InSpace, Static, Placed };
inline constexpr PartState kAllStates[] = {PartState::InHand, PartState::OnTool, PartState::OnBaseSlide,
                                           PartState::OnBaseStatic, PartState::InSpace, PartState::Static,
                                           PartState::Placed};
std::string_view name(PartState s);  // "INHAND", ...

enum class Event {
  Grab,                    // a hand (or both) closes on the part
  Release,                 // the holding hand(s) open away from the part's mate
  ToolAttach,              // a tool (hoist) takes the part
  ToolDetach,              // the tool lets go away from the part's mate
  ConstraintRecognized,    // released (by hand or tool) near its mate on the base, within tolerances
  StaticFrictionOvercome,  // e.g. the base was tilted past the static friction angle
  Stopped,                 // kinetic friction brought it to rest
  Blocked,                 // other geometry of the base or the scene stops it
  LostContact,             // it slid off the surface or shaft it was on
  HitEnvironment,          // in flight, it hit the table, an environment object or the base
  ReachedFinalLocation,    // at its assembled pose with all constraints satisfied
};
inline constexpr Event kAllEvents[] = {Event::Grab, Event::Release, Event::ToolAttach, Event::ToolDetach,
                                       Event::ConstraintRecognized, Event::StaticFrictionOvercome, Event::Stopped,
                                       Event::Blocked, Event::LostContact, Event::HitEnvironment,
                                       Event::ReachedFinalLocation};
std::string_view name(Event e);  // "grab", ...

enum class Hands { None, Left, Right, Both };

// What guards look at.
struct GuardContext {
  GuardContext() = default;
  GuardContext(Category c, Hands h) : category(c), hands(h) {}
  Category category = Category::OneHand;
  Hands hands = Hands::None;  // for Grab: which hands close on the part
  // For ConstraintRecognized and ReachedFinalLocation: a constraint partner of the part that is not PLACED
  // yet (empty: every partner is, or the part's constraints are all to the base).
  std::string unplacedPartner;
};

enum class Guard {
  None,
  CanGrab,     // one-hand: either hand or both; two-hand: both hands; tool-lifted: refused
  Dynamic,     // only one-hand parts get dynamic simulation
  NotDynamic,  // two-hand and tool parts stay where they are released
  PartnersPlaced,  // the parts it is put onto are PLACED (constraints between parts)
};
std::string_view name(Guard g);
// Empty when the guard passes, else why not.
std::string refusal(Guard g, const GuardContext& c);

struct Transition {
  PartState from;
  Event event;
  Guard guard;
  PartState to;
  std::string_view why;  // one line for the printed table and the diagram
};

// The table. Rows with the same (from, event) are tried in order; the first whose guard passes wins.
const std::vector<Transition>& transitionTable();

struct Outcome {
  bool accepted = false;
  PartState to = PartState::Static;
  std::string reason;  // for a refusal: why (no row, or every guard's refusal)
};
Outcome fire(PartState from, Event e, const GuardContext& c);

// The table as text (vaw-sim states) and as Graphviz (docs/states.dot).
std::string tableText();
std::string tableDot();

}  // namespace vaw::interact
