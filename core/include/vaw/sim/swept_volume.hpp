#pragma once
// The space a carried part's path needs over a span of a recorded session (docs/swept-volume.md): the
// part's poses gathered from a replay and swept (vaw/swept_volume.hpp), with the clearance of the same path.
#include <memory>
#include <optional>

#include <Eigen/Geometry>

#include "vaw/swept_volume.hpp"
#include "vaw/sim/clearance.hpp"
#include "vaw/sim/session.hpp"

namespace vaw::sim {

class Scene;

// How far a part's true surface may lie outside its mesh: a CAD part's chordal deflection (its facets
// are chords of its curved faces), 0 for a mesh that is the part.
double tessellationSag(const Part& part);

struct SweptVolumeOptions {
  double voxel = 0.001;             // m
  bool relativeToBase = false;      // the path in the base's frame, placed where the base is at the first step
  std::optional<double> from, to;   // s: the span; unset: every step the part is INHAND or ONTOOL
  double memoryMB = 0.0;            // what the grid may take while it works; 0: half the machine's memory
};

// Replays `session` on `scene` and sweeps the part through the span. Throws vaw::InputError (naming the
// session file and the field) when the span holds no step, the voxel is not a positive length, the grid
// would be too large, or relativeToBase is asked for a scene without a base or for the base itself.
SweptVolume sweptVolume(const std::shared_ptr<const Scene>& scene, const Session& session, PartId part,
                        const SweptVolumeOptions& options = {});

struct SweptPathAndClearance {
  SweptVolume swept;
  ClearanceReport clearance;
};

// The swept volume and the clearance of the same part in one replay (the Path panel and `vaw-sim sweep`
// want both); each takes its span from its own options. Throws as sweptVolume and clearanceAlong do.
SweptPathAndClearance sweptVolumeAndClearance(const std::shared_ptr<const Scene>& scene, const Session& session, PartId part,
                                              const SweptVolumeOptions& swept, const ClearanceOptions& clearance);

}  // namespace vaw::sim
