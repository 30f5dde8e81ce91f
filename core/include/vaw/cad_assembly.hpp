#pragma once
// A CAD assembly (a STEP file read by the importer plugin) made ready to assemble (docs/step.md): one
// part per solid instance with its mass properties from the exact B-rep, the file's assembled pose as
// every part's final pose, the base (the heaviest part unless named), the constraints found in the
// geometry, and the other parts laid out on the table beside the base, each resting on a stable face.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "vaw/assembly.hpp"
#include "vaw/importer.hpp"

namespace vaw {

struct LoadOptions;

// Builds the assembly from what the importer read. Throws InputError naming the file for a file without
// a usable solid, LoadCancelled when `progress` says stop.
Assembly assemblyFromCad(ImportedMesh imported, const std::filesystem::path& file, const LoadOptions& options,
                         const ProgressFn& progress = {});

// "fnv1a64:" and the 16 hex digits of the FNV-1a hash of the file's bytes; throws InputError naming it.
std::string fileContentHash(const std::filesystem::path& file);

// The orientation in which a part rests on a horizontal table: `preferred` (its assembled orientation, so
// that it is picked up as it goes in) when its centre of mass lies over its support there; otherwise the
// stable one with the lowest centre of mass among the candidate faces (its planar faces' normals and its
// principal axes, pointing down).
Eigen::Matrix3d restingOrientation(const TriMesh& mesh, const Eigen::Vector3d& centerOfMass, const Principal& principal,
                                   const CadSolid* solid, const std::optional<Eigen::Matrix3d>& preferred = std::nullopt);

// Poses for the parts other than `base` (whose pose is kept) side by side on the table top (z = tableTop)
// in rows beside the base, none overlapping, `gap` apart. `orientations` are the resting orientations.
std::vector<Eigen::Isometry3d> layOutBeside(const std::vector<Part>& parts, PartId base,
                                            const std::vector<Eigen::Matrix3d>& orientations, double tableTop, double gap);

}  // namespace vaw
