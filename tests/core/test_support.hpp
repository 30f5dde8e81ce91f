#pragma once
#include <filesystem>
#include <string>

#include "bundled.hpp"
#include "vaw/importer.hpp"

namespace vaw::test {

// A fresh folder under the system temp dir, removed at the end of the test program.
std::filesystem::path tempDir();
std::filesystem::path writeFile(const std::filesystem::path& path, const std::string& text);
// An ASCII STL of a mesh, triangle by triangle.
std::string asciiStl(const TriMesh& mesh);

}  // namespace vaw::test
