#pragma once
// Which order puts an assembly together, found from its geometry before anyone tries (docs/evaluation.md).
// Every part's ways home, one per direction its constraints give (off a mated face, along an insert's axis
// from either end), are swept through the assembly at its final poses with the collision module's time of
// impact, pair by pair, so each way out lists every part in it, not only the first. Assembly by
// disassembly then takes out, round by round, the parts that have a way out clear of the parts still in
// and that no part still in is constrained to; the reverse is an order that puts the assembly together.
// What stays in when nothing more can come out can be inserted by no order, each with what blocks it.
#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "vaw/assembly.hpp"
#include "vaw/importer.hpp"

namespace vaw::collision {
class CollisionWorld;
}

namespace vaw::eval {

struct Blocker {
  PartId by = 0;
  // m travelled out from home before the part meets it; 0 when the two interfere at their final poses.
  double distance = 0.0;
  // The sweep ran out of its iteration limit at `distance` without deciding: counted as in the way, since
  // a way not known to be free is no way home.
  bool undecided = false;
};

// One way home: the part comes in along -out.
struct Direction {
  Eigen::Vector3d out = Eigen::Vector3d::UnitZ();  // world, unit
  std::string from;  // what gives the direction: "insert stud-1 on base-plate", "... (other end)", "world +z"
  std::optional<std::size_t> constraint;  // the constraint that gives it (index into Assembly::constraints)
  bool alongAxis = false;           // an insert's axis (the sweep slides along coaxial surfaces)
  std::vector<Blocker> blockers;    // every part in the way at the final poses, nearest first
  double length = 0.0;              // m swept out: until the part's trailing side passed the assembly's leading side
};

struct PartCheck {
  PartId part = 0;
  // The constraints' home directions first (the way the recognition saw the part come in), then the other
  // end of each insert's axis. A part without constraints is tried along the six world axes, +z first.
  std::vector<Direction> directions;
};

struct Precedence {
  enum class Reason { Partner, Blocks };
  PartId before = 0, after = 0;
  // Partner: `after` is constrained to `before` (the workbench places a part only on placed partners).
  // Blocks: `after` stands in the way `before` comes home by.
  Reason reason = Reason::Partner;
};

struct Stuck {
  PartId part = 0;
  // Per direction (PartCheck::directions' order), the parts still in the assembly in the way.
  std::vector<std::vector<PartId>> blockers;
  // Constrained to parts that are stuck themselves (it could come home, but its partner cannot).
  std::vector<PartId> waitsFor;
};

struct SequencePlan {
  std::optional<PartId> base;
  std::vector<PartCheck> checks;        // every part with a final pose but the base, by PartId
  std::vector<PartId> order;            // base first, then every part some order can insert
  std::vector<int> way;                 // per order entry: the direction used (-1 for the base)
  std::vector<int> step;                // per order entry: the disassembly round, reversed (parts of one step need no order among them)
  std::vector<Precedence> precedence;   // what the order found must respect, one entry per pair and reason
  std::vector<Stuck> stuck;             // no order inserts these
  std::vector<PartId> skipped;          // parts without a final pose: not in the sequence
  // Parts that come home together, put together beforehand as a sub-assembly (the table of a rotary table
  // with all it carries, lowered onto its shaft): each its parts in the order they are put together, the
  // first the one whose way the whole comes home by (its `way` in the order); the others' way entries are -1.
  struct SubAssembly {
    std::vector<PartId> parts;
    Eigen::Vector3d out = Eigen::Vector3d::UnitZ();  // world: the whole comes in along -out
  };
  std::vector<SubAssembly> subAssemblies;
  std::vector<int> subAssembly;         // per order entry: index into subAssemblies, -1 for a part on its own
  // Parts no rigid motion puts in place because they wrap others (a belt round two pulleys, a spring, a hose:
  // a ring held in every way by what passes through it): flexible, fitted by hand after what they wrap, last
  // in the order (their way entries -1), not among the stuck.
  struct Wrap {
    PartId part = 0;
    std::vector<PartId> wraps;
  };
  std::vector<Wrap> wraps;
  [[nodiscard]] const Wrap* wrapOf(PartId p) const;
  int pairChecks = 0;                   // a part moved along a way past another: the checks run
  int reused = 0;                       // pair sweeps answered by an earlier one of the same shapes, placed alike
  int undecided = 0;                    // of them, those that ran out of their iteration limit
  int evaluations = 0;                  // distance and blocked checks in them
  [[nodiscard]] bool complete() const { return stuck.empty(); }
  // The direction a part in the order came home by, or nullptr (the base; a sub-assembly's parts but its first).
  [[nodiscard]] const Direction* wayOf(PartId p) const;
  // The sub-assembly a part came home in, or nullptr.
  [[nodiscard]] const SubAssembly* subAssemblyOf(PartId p) const;
  [[nodiscard]] const PartCheck* checkOf(PartId p) const;
};

struct SequenceOptions {
  double tolerance = 1e-5;  // m, where along its way a block is located
  double maxStep = 1e-3;    // m: within this of another part, the blocked check every maxStep of motion
  // Two parts that clash at home (collision/interference.hpp) come home through each other along the ways
  // their constraints give them, the way saying so; false: a clash blocks (whether a sub-assembly comes
  // apart at all, cad_units.cpp).
  bool throughClashes = true;
};

// How a part travels home along a way out `out`, for people: "down", "up", "along +x", or the components
// "along (0.707, 0.000, -0.707)".
std::string travelText(const Eigen::Vector3d& out);

// Which of two constrained parts goes first, from how they can move (a non-directional blocking graph
// in the sense of Wilson and Latombe, restricted to the constraints' ways): for every pair of parts that
// share a constraint (the base aside), each part's ways out (every constraint's direction it is in, off a
// mate's plane and along an insert's axis both ways) are swept at `home` (the parts' assembled poses, by
// PartId) against the other part and, where that decides it, the base. A part all of whose ways the base
// leaves open are blocked by the other needs the other absent, so it goes first: the bracket before the
// bolt whose head clamps it. Returns (first, second) for the pairs where the geometry puts first the part
// the constraints name as the constrained one (so the partner is to be swapped); pairs where neither or
// each blocks the other keep the partner they have. `sweeps` counts the pair sweeps run. `progress` is
// asked before each pair; false stops with LoadCancelled.
std::vector<std::pair<PartId, PartId>> geometricPrecedence(const Assembly& assembly, const std::vector<Eigen::Isometry3d>& home,
                                                           const SequenceOptions& options = {}, int* pairChecks = nullptr,
                                                           const PairProgress& progress = {});

// The interval a box covers along a unit direction: where a part's box starts and ends along its way.
std::pair<double, double> extentAlong(const Eigen::AlignedBox3d& box, const Eigen::Vector3d& direction);

// The assembly put together: every part at its final pose; the base, and parts without a final pose,
// where they stand. By PartId.
std::vector<Eigen::Isometry3d> homePoses(const Assembly& assembly);

// Throws vaw::Error when the assembly has no base. `progress` (may be empty) is asked between parts;
// returning false stops with LoadCancelled.
SequencePlan planSequence(const Assembly& assembly, const SequenceOptions& options = {}, const ProgressFn& progress = {});
// The same in a collision world built from the assembly with every part at its home pose (homePoses), for a
// caller that has one.
SequencePlan planSequence(const Assembly& assembly, const collision::CollisionWorld& atHome, const SequenceOptions& options = {},
                          const ProgressFn& progress = {});

}  // namespace vaw::eval
