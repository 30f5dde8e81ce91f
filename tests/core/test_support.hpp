#pragma once
#include <filesystem>
#include <string>

#include "vaw/importer.hpp"

namespace vaw::test {

// A registry with the build tree's importer plugins loaded (fails the test if none load).
const ImporterRegistry& importers();
std::filesystem::path resources();

// A fresh folder under the system temp dir, removed at the end of the test program.
std::filesystem::path tempDir();
std::filesystem::path writeFile(const std::filesystem::path& path, const std::string& text);
// An ASCII STL of a mesh, triangle by triangle.
std::string asciiStl(const TriMesh& mesh);

}  // namespace vaw::test
