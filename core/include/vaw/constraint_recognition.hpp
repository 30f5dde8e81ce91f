#pragma once
// Assembly constraints found in the geometry of an assembled CAD model (docs/step.md, "Constraints
// recognised"): an insert where a part's cylindrical face is coaxial with another's (a shaft in a bore,
// equal radii or a clearance), a mate where planar faces meet face to face over a real area, and the seat of
// a countersunk head where its cone lies on the countersink's (on the screw's insert). Works on the
// exact surfaces a CAD importer reports (vaw/importer.hpp, CadFace), at the parts' assembled poses.
#include <Eigen/Geometry>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "vaw/assembly.hpp"
#include "vaw/importer.hpp"

namespace vaw {

struct RecognitionTolerances {
  double angle = 1e-4;            // rad between axes or normals
  double distance = 1e-5;         // m between coaxial axes or coplanar planes (exports round at ~1e-6 m)
  double maxClearance = 0.002;    // m, radial play still counted as an insert ...
  double maxClearanceRel = 0.15;  // ... and at most this fraction of the bore's radius
  double minOverlapRel = 1e-3;    // overlap below this fraction of the smaller face is a touch at an edge
};

// One part at its assembled pose (world frame) with its CAD solid.
struct RecognitionPart {
  std::shared_ptr<const CadSolid> solid;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
};

// One constraint between two parts, geometry in world coordinates at the assembled pose. `a` and `b` are
// indices into the input; the faces index each solid's CadSolid::faces. For a mate, `direction` is a's
// outward face normal (pointing into b); for an insert, the common axis direction.
struct FoundConstraint {
  Constraint::Type type = Constraint::Type::Mate;
  std::size_t a = 0, b = 0;
  std::size_t faceA = 0, faceB = 0;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();
  Constraint::Found found;
};

// Every constraint between every pair of parts, in a deterministic order (by pair, then kind, then face).
// A pair whose faces only meet at an edge or a point gives none. Parts without a solid are skipped.
// Candidate pairs come from a sweep over the parts' boxes, not from every pair. `progress` is asked before
// each candidate pair; false stops with LoadCancelled.
std::vector<FoundConstraint> recognizeConstraints(const std::vector<RecognitionPart>& parts,
                                                  const RecognitionTolerances& tol = {}, const PairProgress& progress = {});

// The face of `s` whose exact surface passes nearest `point` (the solid's frame, m), within `tolerance` (m):
// a plane by the point's distance to it, a cylinder or a cone by its distance to that surface within the
// face's axial extent (with `tolerance` of slack at the ends). Where a face has triangles the point must also be within
// `tolerance` of them, since the surface goes on past the face's edges; a face of another kind is matched
// by its triangles alone. None when no face is that near.
std::optional<std::size_t> faceAt(const CadSolid& s, const Eigen::Vector3d& point, double tolerance);

// What recognition makes of one chosen pair of faces: the constraint, or in a person's words why they are
// none ("the axes are 1.4 mm apart").
struct FacePairResult {
  std::optional<FoundConstraint> found;
  std::string why;
};
// Face `faceA` of part `a` and face `faceB` of part `b` (indices into `parts` and their solids' faces) put
// through the tests recognizeConstraints applies, at the poses `parts` holds: two cylinders as an insert,
// two cones as a countersunk head's seat (an insert along the countersink's axis), two planes as a mate.
// The found constraint's `a` is `a`.
FacePairResult constraintFromFaces(const std::vector<RecognitionPart>& parts, std::size_t a, std::size_t faceA, std::size_t b,
                                   std::size_t faceB, const RecognitionTolerances& tol = {});

// A pair of faces that looks like a fit and was not taken (docs/step.md, "Near misses"): two coaxial
// cylinders of opposite kinds, or two facing planes over a common area, refused by one of recognition's
// tests; `why` says which, with what it measured and the limit ("the bore is 2.3 mm larger in radius than
// the shaft: more play than 2 mm"). So that a missing constraint can be seen, not guessed.
struct NearMiss {
  std::size_t a = 0, b = 0;          // indices into the parts
  std::size_t faceA = 0, faceB = 0;  // into each solid's faces
  Constraint::Type type = Constraint::Type::Insert;
  std::string why;
  double value = 0.0, limit = 0.0;  // what the refusing test measured and its limit (m, m^2 or rad)
};
// Every near miss between the parts, in the order recognition tries the pairs. Nearly coaxial: axes within
// 1 degree and max(0.5 mm, a tenth of the smaller radius) of each other; nearly facing: normals within 1
// degree of opposed, the planes within 0.5 mm, their faces over each other by more than an edge.
std::vector<NearMiss> nearMisses(const std::vector<RecognitionPart>& parts, const RecognitionTolerances& tol = {});
// Those of a CAD assembly's parts where they end up (collision::assembledPoses); none for other assemblies.
std::vector<NearMiss> nearMisses(const Assembly& assembly);

// The area common to two planar faces that lie in one plane (face A's triangles against face B's), m^2.
double coplanarOverlapArea(const CadSolid& a, const CadFace& fa, const Eigen::Isometry3d& poseA, const CadSolid& b,
                           const CadFace& fb, const Eigen::Isometry3d& poseB);

// Turns found constraints into the assembly's: one per found pair and kind, with the part and the partner
// chosen by assembly order (docs/step.md, "Who goes first"): `first` holds (before, after) pairs the
// geometry decided (eval::geometricPrecedence); for the other pairs the base goes first, then the part
// nearer the base in the contact graph, then for an insert the shaft before the part with the bore (a nut
// goes onto its bolt), then the one whose lowest point is lower, then the heavier. Geometry in each one's
// frame, the base as an empty partner, and the direction each part comes home from. `finalPoses` are the
// parts' assembled poses. `contacts` are further pairs of parts that touch (the assembly's other
// constraints, when one pair is added to them), counted in the assembly order only.
std::vector<Constraint> constraintsFromFound(const std::vector<FoundConstraint>& found, const std::vector<Part>& parts,
                                             PartId base, const std::vector<Eigen::Isometry3d>& finalPoses,
                                             const std::vector<std::pair<PartId, PartId>>& contacts = {},
                                             const std::vector<std::pair<PartId, PartId>>& first = {});

}  // namespace vaw
