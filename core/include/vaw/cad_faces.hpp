#pragma once
// Faces of one surface made one face (docs/step.md, "Split surfaces"). CAD systems write a closed
// cylinder as two or four faces (each seamless face divided at its seams), and a flat face interrupted by
// a pocket or split by the exporter as several faces on one plane. The constraint recognition, the
// collision module's supports and the constraints panel reason about surfaces, not about how a kernel cut
// them into faces, so a solid's faces are merged before anything reads them.
#include <cstddef>

#include "vaw/importer.hpp"

namespace vaw {

struct FaceMergeTolerances {
  double angle = 1e-4;      // rad between two cylinders' axes or two planes' normals
  double distance = 1e-5;   // m between axes, between radii, between parallel planes
};

// Merges, in place, the faces of `solid` that lie on one surface: cylinders with the same axis, radius and
// convexity (analytic or recognised from a B-spline) become one cylinder whose axial extent is the union of
// theirs; planes with the same outward normal and offset become one plane. Areas add up, `fromSpline` is
// kept when any part was, the first face's point and direction are kept. The triangles are reordered so
// that each merged face's triangles are contiguous again; the vertices are untouched. Faces of kind Other
// are never merged. Returns how many faces were merged away (0: the solid is unchanged).
std::size_t mergeSplitFaces(CadSolid& solid, const FaceMergeTolerances& tol = {});

}  // namespace vaw
