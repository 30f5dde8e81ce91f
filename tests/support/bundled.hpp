#pragma once
// The build tree's importer plugins and bundled resources, for tests (GoogleTest).
#include <filesystem>
#include <string>

#include "vaw/assembly.hpp"
#include "vaw/importer.hpp"

namespace vaw::test {

// A registry with the build tree's importer plugins loaded; a plugin that fails to load, or none at
// all, fails the calling test.
const ImporterRegistry& importers();
// build/share/vaw: scenes/, meshes/, properties/.
std::filesystem::path resources();
// A scene from resources()/scenes, loaded with importers().
Assembly loadBundled(const std::string& sceneFile);

}  // namespace vaw::test
