#pragma once
// Writing a mesh for another program to read: binary STL, the one format every CAD system and slicer
// takes. STL carries no unit; the caller scales to the unit the reader is told of.
#include <string>
#include <string_view>

#include "vaw/mesh.hpp"

namespace vaw {

// The bytes of a binary STL of `mesh` (metres) scaled by `unitsPerMetre` (1000 for millimetres), each
// facet with its normal; `header` (at most 80 bytes are kept) should say the unit. Throws
// std::invalid_argument for a mesh with more facets than the format's 32-bit count.
std::string binaryStl(const TriMesh& mesh, double unitsPerMetre, std::string_view header);

}  // namespace vaw
