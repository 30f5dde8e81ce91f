#pragma once
// Interference at rest, as CAD systems check it (docs/evaluation.md, "Interferences"): every pair of parts
// whose solids meet at their assembled poses, measured (shared volume, deepest penetration, where) and
// classified: touching only, a thread modelled at its tap drill, a press fit, or a clash (anything else:
// a modelling error the user should see).
#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "vaw/assembly.hpp"
#include "vaw/importer.hpp"

namespace vaw::collision {

struct Interference {
  enum class Kind { Contact, Threaded, Press, Clash };
  Kind kind = Kind::Contact;
  PartId a = 0, b = 0;  // a < b
  // The shared volume (m^3), the deepest penetration (m: how far one would have to move out of the other
  // at most) and its middle (world, at the assembled poses). A designed fit's are its band's, exact for the
  // modelled cylinders: pi (R^2 - r^2) times the axial overlap, R - r, the band's middle on the axis. A
  // clash's are measured on the meshes: lines through the common box, 64 to the side, each cut with both
  // solids (docs/evaluation.md says how exact). Zero for a contact.
  double volume = 0.0;
  double depth = 0.0;
  Eigen::Vector3d where = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();  // a clash: the axis of least overlap, the way out
  std::string thread;                                    // Threaded: "M6"
};
std::string_view name(Interference::Kind k);

// Every pair of parts at their assembled poses (`poses`, one per part) whose solids meet, contacts
// included, in order: clashes first, then threaded, press and contact, each by part. Pairs whose boxes are
// apart cost nothing; `progress` (fraction, pair) may stop it with LoadCancelled.
std::vector<Interference> interferences(const Assembly& assembly, const std::vector<Eigen::Isometry3d>& poses,
                                        const PairProgress& progress = {});

// One pair as `world` holds them (the parts at their assembled poses): what the two share, or none when
// they do not meet.
class CollisionWorld;
struct OverlapCache;  // what a run over many pairs keeps between them (the parts taken into the world)
std::optional<Interference> overlapAtRest(const CollisionWorld& world, const Assembly& assembly, PartId p, PartId q,
                                          OverlapCache* cache = nullptr);

// The assembled poses: each part's final pose, the base's own.
std::vector<Eigen::Isometry3d> assembledPoses(const Assembly& assembly);

}  // namespace vaw::collision
