#pragma once
// How close each part's way home comes to the parts already in (docs/evaluation.md, "Ways home: clearance
// and space"). The order search (sequence.hpp) asks only whether a way is free; a way that is free but
// passes a tenth of a millimetre from a neighbour is a way an assembler's hand will not keep to. For every
// part in the order, along the way it came home by, from where it is clear of the assembly to its final
// pose: its least distance to each part already in, where on the way, and the two nearest points; and,
// when asked, the space the way needs as a swept volume (sim/swept_volume.hpp). Two kinds of neighbour are
// not near misses by design: the parts it slides on (the partners of its inserts whose axis is the way:
// a nut on its stud, a sleeve on its pin, whatever their fit), left out; and the parts it comes to rest
// on (touching it at home), measured only from `threshold` (and the search's tolerance) out, so that the last approach onto its seat
// is not counted but what it passes on the way there is (a nut 1 mm from the bracket's upright it is
// screwed down beside).
#include <optional>
#include <vector>

#include <Eigen/Geometry>

#include "vaw/evaluation/sequence.hpp"
#include "vaw/swept_volume.hpp"

namespace vaw::eval {

struct WayClearanceOptions {
  double threshold = 0.005;  // m: a part passing closer than this to one it does not rest on is a near miss
  double reach = 0.05;       // m: parts never this close along the way are left out
  // m: each least distance found is at most this above the true one (or 5 % of how far it lies beyond the
  // threshold, when that is more), and never below it.
  double tolerance = 1e-4;
  double voxel = 0.0;        // m: the swept volume's voxel edge; 0 leaves the swept volume out
  std::optional<PartId> only;  // this part's way alone (the parts before it in the order still count as in)
};

struct WayObject {
  PartId part = 0;
  double least = 0.0;  // m
  double at = 0.0;     // m out from home along the way, where it is least
  Eigen::Vector3d onPart = Eigen::Vector3d::Zero(), onOther = Eigen::Vector3d::Zero();  // world, the part there
};

struct WayClearance {
  PartId part = 0;
  int way = -1;                          // index into the part's PartCheck::directions
  Eigen::Vector3d out = Eigen::Vector3d::UnitZ();  // the way out (it comes home along -out)
  double length = 0.0;                   // m from where it is clear of the assembly to home
  std::vector<PartId> guides;            // parts it slides on along the way, left out
  std::vector<PartId> seatedOn;          // other parts already in that it touches at home
  // Parts already in within reach along the way, nearest first; a seat only when it comes within the
  // threshold before the last approach.
  std::vector<WayObject> objects;
  // The way's swept volume, when a voxel was given: its grid and volume, without its mesh (surface() makes
  // it again; a thousand ways' meshes held at once took 410 MB).
  std::optional<SweptVolume> swept;

  // The nearest part it passes, or nullptr when none comes within reach.
  [[nodiscard]] const WayObject* nearest() const { return objects.empty() ? nullptr : &objects.front(); }
  [[nodiscard]] bool nearMiss(double threshold) const { return !objects.empty() && objects.front().least < threshold; }
};

// One entry per part of plan.order after the base, in the order. `progress` (may be empty) hears of each
// part; false stops with vaw::LoadCancelled. Throws vaw::InputError for options that are not finite
// lengths (threshold, reach or voxel below 0, tolerance not above 0).
std::vector<WayClearance> wayClearances(const Assembly& assembly, const SequencePlan& plan, const WayClearanceOptions& options = {},
                                        const ProgressFn& progress = {});

}  // namespace vaw::eval
