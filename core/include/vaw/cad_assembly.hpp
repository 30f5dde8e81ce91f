#pragma once
// A CAD assembly (a STEP file read by the importer plugin) made ready to assemble (docs/step.md): one
// part per solid instance with its mass properties from the exact B-rep, the file's assembled pose as
// every part's final pose, the base (the part it stands on unless named), the constraints found in the
// geometry, and the other parts laid out on the table beside the base, each resting on a stable face.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vaw/assembly.hpp"
#include "vaw/constraint_recognition.hpp"
#include "vaw/importer.hpp"

namespace vaw {

struct LoadOptions;

// Builds the assembly from what the importer read. Throws InputError naming the file for a file without
// a usable solid, LoadCancelled when `progress` says stop. `massSource` Brep takes each solid's mass
// properties from its boundary representation with the mesh's as the cross-check; Mesh (solids made from
// a mesh file's parts by cadSolidFromMesh) takes the mesh's alone.
Assembly assemblyFromCad(ImportedMesh imported, const std::filesystem::path& file, const LoadOptions& options,
                         const ProgressFn& progress = {}, MassSource massSource = MassSource::Brep);

// One part of a mesh file (STL, OBJ, glTF, ...) as a CAD solid, so that a mesh assembly is laid out and its
// constraints found like a STEP file's: the faces are the collision module's surface patches (cylinders
// first, then the planar patches that are not facets of a cylinder, then the rest as one face of kind
// Other), the triangles reordered to be contiguous per face, and the mass properties the mesh's. `mesh`
// is closed and outward oriented, in metres; the solid's frame has its origin at the mesh's centroid,
// returned in `centroid` so that the part can be placed where it was.
std::shared_ptr<const CadSolid> cadSolidFromMesh(const TriMesh& mesh, const std::string& product, Eigen::Vector3d& centroid);

// "xxh3:" and the 16 hex digits of the XXH3 64-bit hash of the file's bytes; throws InputError naming it.
std::string fileContentHash(const std::filesystem::path& file);
// The same as scenes saved before XXH3 wrote it: "fnv1a64:" and FNV-1a's (read to compare, never written).
std::string fileContentHashFnv(const std::filesystem::path& file);

// The part a fitter builds the assembly on (docs/step.md, "The base"): the part the assembly stands on.
// For each way down (the file's -z and -y first, as CAD systems model Z or Y up; the other four where
// neither has a footing), every part's planar faces facing that way with nothing of another part below
// them (their exposed footing) are measured; the part with the largest footing is the base, among parts
// in a constraint when there are any, the heavier of two within 5 %. `poses` are the file's.
struct BaseChoice {
  PartId base = 0;
  Eigen::Vector3d down = -Eigen::Vector3d::UnitZ();  // the file's direction the footing faces
  double footing = 0.0;                               // m^2
  std::string reason;                                  // for people
};
BaseChoice chooseBase(const std::vector<Part>& parts, const std::vector<Eigen::Isometry3d>& poses,
                      const std::vector<FoundConstraint>& found);

// The orientation in which a part rests on a horizontal table: `preferred` (its assembled orientation, so
// that it is picked up as it goes in) when its centre of mass lies over its support there; otherwise the
// stable one with the lowest centre of mass among the candidate faces (its planar faces' normals and its
// principal axes, pointing down).
Eigen::Matrix3d restingOrientation(const TriMesh& mesh, const Eigen::Vector3d& centerOfMass, const Principal& principal,
                                   const CadSolid* solid, const std::optional<Eigen::Matrix3d>& preferred = std::nullopt);

// Which way a CAD assembly stands (docs/step.md, "Which way is up"): the turn applied to the file's frame.
// `up` "auto": the base rests on its most stable face (of its largest planar faces and principal axes, the
// stable one under which its centre of mass lies lowest; of two equally low, the one facing away from
// `assemblyCentre`, the assembly's centre of mass in the file, so the rest stands on the base), unless the
// file's own orientation is as good; a file axis ("+x", "-x", "+y", "-y", "+z", "-z"): that axis of the
// file points up; three numbers ("0 0.6 0.8"): that direction of the file points up (a face put down
// in the viewport, upForFaceDown). `basePose` is the base's pose in the file.
// `footing`: the file's direction the base's footing faces (BaseChoice::down); "auto" stands the base on it
// where the base is stable so.
Eigen::Matrix3d assemblyUp(const Part& base, const Eigen::Isometry3d& basePose, const Eigen::Vector3d& assemblyCentre,
                           const std::string& up, const std::optional<Eigen::Vector3d>& footing = std::nullopt);
// True for "auto", the six file axes and a direction of three finite numbers, not all zero.
bool validUpChoice(const std::string& up);
// The file direction an up choice names (unit); none for "auto" and anything invalid.
std::optional<Eigen::Vector3d> upDirection(const std::string& up);
// What validUpChoice accepts, for error messages.
inline constexpr const char* kUpChoices = "\"auto\", a file axis (+x, -x, +y, -y, +z, -z) or a file direction as three numbers";
// "This face down": the up choice that makes a face of the loaded CAD assembly's base, with outward
// `normal` in the base's own frame, rest on the table (a file axis when the face is square to one, else
// the direction's three numbers). None for an assembly not read from a CAD file.
std::optional<std::string> upForFaceDown(const Assembly& assembly, const Eigen::Vector3d& normal);

// Poses for the parts other than `base` (whose pose is kept) side by side on the table top (z = tableTop)
// in rows beside the base, none overlapping, `gap` apart. `orientations` are the resting orientations.
std::vector<Eigen::Isometry3d> layOutBeside(const std::vector<Part>& parts, PartId base,
                                            const std::vector<Eigen::Matrix3d>& orientations, double tableTop, double gap);
// For a product too large to wait beside its base: every part by the side of the base nearest where it goes
// (its finalPose), in rows along that side, each as near its place along the side as the row allows, as few
// rows as hold them; none overlapping, the first row `gap` from the base, neighbours a finger's width apart.
std::vector<Eigen::Isometry3d> layOutAround(const std::vector<Part>& parts, PartId base,
                                            const std::vector<Eigen::Matrix3d>& orientations, double tableTop, double gap);

}  // namespace vaw
