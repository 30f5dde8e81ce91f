// The reader's result: the CBOR document vaw-step-import writes and the STEP plugin reads (docs/step.md,
// "The reader's result"). Both sides include this header, so the format's version and the codes of the
// surface kinds are written once; the plugin refuses a result of another version, which a reader left
// over from another build would write.
//
//   {"version": 1, "format": "STEP AP214", "unit": "millimetre", "warnings": [...],
//    "solids": [{"product", "volume", "centroid", "inertia", "area", "deflection", "vertices" (binary,
//                float64 x y z), "triangles" (binary, int32 a b c), "faces": [{"surface", "area", "first",
//                "count", "point", "direction", "fromSpline", "radius", "convex", "axialMin",
//                "axialMax", "halfAngle"}], "color"}],
//    "root": {"name", "location" (3x4 row-major), "color", "solid" (index) | "children": [...]}}
//   or, for a bad file, {"version": 1, "error": {"field", "expected", "found"}}
// Lengths in metres, in each solid's own frame.
#pragma once

namespace vaw::step {

inline constexpr int kResultVersion = 2;

enum class SurfaceKind : int { Plane = 0, Cylinder = 1, Other = 2, Cone = 3 };

// The reader skips assemblies nested deeper than 200 levels; each level is two CBOR levels (the node's
// map and its children's array). The plugin refuses deeper results before its recursive parse.
inline constexpr int kMaxAssemblyDepth = 200;
inline constexpr int kMaxResultDepth = 2 * kMaxAssemblyDepth + 16;

}  // namespace vaw::step
