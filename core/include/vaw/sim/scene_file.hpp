#pragma once
// Saving a scene with its tuning: the file the scene was loaded from, as written (its keys, order and
// comments), with a "settings" block (docs/scene-format.md) holding what the workbench's panels set on the
// running world: the step rate, the gravity scales, the rotation method, every material's friction and the
// per-part friction overrides. Opening the saved file starts the simulation with the same tuning.
#include <filesystem>

#include "vaw/assembly.hpp"
#include "vaw/sim/world.hpp"

namespace vaw::sim {

// Writes `loaded.source` with the tuning of `world` to `target` (which may be the source itself), as
// format version 2. Relative paths in it (meshes, property files) are rewritten to point from target's
// folder to the same files. The file is written whole to a temporary file next to the target and then
// renamed over it, so an interrupted save leaves the previous file. Errors are vaw::InputError naming the
// file.
// An assembly read from a CAD file is saved as a version 3 scene that refers to that file by a relative
// path with its content hash, and holds the base, the constraints and the tuning (docs/scene-format.md).
void saveScene(const Assembly& loaded, const World& world, const std::filesystem::path& target);

}  // namespace vaw::sim
