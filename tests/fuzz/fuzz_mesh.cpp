// The mesh checks on any triangle soup: the input is read as a binary STL (80-byte header, a count,
// 50 bytes per triangle, corners as 32-bit floats, so also NaN, infinity and 3e38), then welded, cleaned,
// checked, measured and classified into surface patches as the loader and the collision world do.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "fuzz_support.hpp"
#include "vaw/collision/surface_patches.hpp"
#include "vaw/mass_properties.hpp"
#include "vaw/mesh.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 84) return 0;
  const std::size_t count = std::min<std::size_t>((size - 84) / 50, 4096);
  vaw::TriMesh mesh;
  for (std::size_t t = 0; t < count; ++t) {
    float record[12];
    std::memcpy(record, data + 84 + 50 * t, sizeof record);
    const int base = static_cast<int>(mesh.vertices.size());
    for (int k = 0; k < 3; ++k) mesh.vertices.emplace_back(record[3 + 3 * k], record[4 + 3 * k], record[5 + 3 * k]);
    mesh.triangles.emplace_back(base, base + 1, base + 2);
  }
  // The header's first byte picks the weld tolerance's scale, to reach the grid's far cells too.
  const double tolerance = std::ldexp(1.0, static_cast<int>(data[0]) - 160);
  const vaw::MeshCheck check = vaw::repairMesh(mesh, tolerance, tolerance * tolerance).check;
  (void)check.summary();
  const vaw::MassProperties mp = vaw::massPropertiesFromMesh(mesh, 7850.0);
  (void)vaw::inertiaProblem(mp.inertiaCm, 1e-6);
  // Surface patches are made only for meshes the loader accepts: closed, oriented, enclosing a volume,
  // within the world's bounds.
  const bool inBounds = std::all_of(mesh.vertices.begin(), mesh.vertices.end(),
                                    [](const Eigen::Vector3d& v) { return v.cwiseAbs().maxCoeff() <= 1000.0; });
  if (check.valid() && mp.volume > 0.0 && inBounds) (void)vaw::collision::classifySurfaces(mesh);
  return 0;
}
