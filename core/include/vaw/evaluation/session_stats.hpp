#pragma once
// What an assembler's session shows (docs/evaluation.md, "After the assembler tried"): the order parts were
// PLACED and, per part, the time from its first grab to PLACED, grabs, tool lifts and drops, refusals with
// their reasons, blocked insertions with what blocked them, the hands and tool used and the distance
// carried; totals for the session; and several sessions (participants) side by side with means and spread.
// Built from the world's transition and refusal logs and a look at the world after every step, so a live
// session, a replayed one and a headset one give the same figures.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vaw/importer.hpp"
#include "vaw/sim/session.hpp"
#include "vaw/sim/world.hpp"

namespace vaw::eval {

struct PartSession {
  PartId part = 0;
  std::string name;
  std::optional<double> firstHandled_s;  // first grab or tool lift
  std::optional<double> placed_s;        // when it became PLACED, if it still is at the end
  int grabs = 0;                         // hand grabs
  int toolLifts = 0;                     // the hoist took it
  int drops = 0;                         // let go away from its mate (by hand or tool)
  std::vector<std::string> refusals;     // "<event>: <reason>", in order
  std::vector<std::string> blocked;      // the causes of Blocked transitions ("blocked by bracket"), in order
  bool left = false, right = false, both = false, hoist = false;  // what held it at some step
  double carried_m = 0.0;                // path of its centre of mass while held
  [[nodiscard]] std::optional<double> timeToPlace() const;
  [[nodiscard]] std::string holders() const;  // "right hand", "left and right hands, hoist", "" ...
};

// A stretch of time a part spent in one state (the timeline).
struct StateSpan {
  PartId part = 0;
  double from_s = 0.0, to_s = 0.0;
  interact::PartState state = interact::PartState::Static;
};

struct SessionStats {
  std::string label;  // participant or file name
  double duration_s = 0.0;
  std::vector<StateSpan> spans;      // every part's states over the session, by part then time
  std::vector<PartSession> parts;    // every part but the base, by PartId
  std::vector<PartId> placedOrder;   // by the time each became PLACED
  int grabs = 0, toolLifts = 0, drops = 0, refusals = 0, blocked = 0;
  double carried_m = 0.0;
  [[nodiscard]] const PartSession* find(PartId p) const;
};

// Watches a world step by step (call observe() after every step, from the start) and sums it up.
class SessionObserver {
 public:
  explicit SessionObserver(const sim::World& world);
  void observe(const sim::World& world);
  [[nodiscard]] SessionStats finish(const sim::World& world, std::string label) const;

 private:
  std::vector<Eigen::Vector3d> lastCentre_;
  std::vector<bool> wasHeld_;
  std::vector<PartSession> parts_;
};

// Replays a recorded session on its scene and sums it up. `progress` hears how far the replay is, about a
// hundred times; when it returns false the replay stops with vaw::LoadCancelled.
SessionStats sessionStats(std::shared_ptr<const sim::Scene> scene, const sim::Session& session, std::string label,
                          const ProgressFn& progress = {});

struct Spread {
  int n = 0;  // sessions with a value
  double mean = 0.0, sd = 0.0, min = 0.0, max = 0.0;  // sd: sample standard deviation (0 for n < 2)
};
Spread spread(const std::vector<double>& values);

// Several sessions of one assembly side by side: per part (by name, in the first session's order) the
// spread over the sessions of its time to place (sessions where it was placed), grabs, drops, refusals and
// distance carried.
struct PartAcross {
  std::string name;
  int placedIn = 0;
  Spread timeToPlace, grabs, drops, refusals, carried;
};
struct Comparison {
  std::vector<SessionStats> sessions;
  std::vector<PartAcross> parts;
  Spread duration, placed;
};
Comparison compare(std::vector<SessionStats> sessions);

}  // namespace vaw::eval
