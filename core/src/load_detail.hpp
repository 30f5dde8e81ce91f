#pragma once
// Shared by the scene loader and the CAD assembly builder (private to the core's sources).
#include <string>

#include "vaw/error.hpp"
#include "vaw/importer.hpp"
#include "vaw/mesh.hpp"

namespace vaw::detail {

// Welds, removes degenerate triangles (with a warning) and rejects meshes that are not a solid, naming
// `file`.
void validateSolid(TriMesh& mesh, const std::string& file, Diagnostics& warnings, const ProgressFn& progress);

}  // namespace vaw::detail
