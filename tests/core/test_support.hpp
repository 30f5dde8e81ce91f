#pragma once
#include <filesystem>
#include <string>

#include "bundled.hpp"
#include "files.hpp"
#include "vaw/importer.hpp"

namespace vaw::test {
// An ASCII STL of a mesh, triangle by triangle.
std::string asciiStl(const TriMesh& mesh);

}  // namespace vaw::test
