#pragma once
// The world's bounds: the ranges every file vaw reads is checked against, with the field named, before
// anything is built from it. Beyond them the simulation would not be meaningful (a hand moving at
// 1000 m/s, a part 1e308 m away) or a library would fail: FCL's trees crashed on a coordinate of
// 1e308, and far-away coordinates made a short run hundreds of times slower. docs/scene-format.md and
// docs/inputs-format.md list them for users.
#include <unistd.h>

#include <cstddef>

namespace vaw::limits {

inline constexpr double kMaxCoordinate = 1000.0;  // m: |x|, |y|, |z| of every position, pose and vertex
inline constexpr double kMinSize = 1e-6;          // m: a primitive's dimensions
inline constexpr double kMaxSize = 100.0;         // m: a primitive's dimensions
inline constexpr double kMinDensity = 0.1;        // kg/m^3 (aerogels are about 1)
inline constexpr double kMaxDensity = 1e5;        // kg/m^3 (osmium is 22,590)
inline constexpr double kMinMass = 1e-6;          // kg, from a property file
inline constexpr double kMaxMass = 1e6;           // kg
inline constexpr double kMaxFriction = 10.0;      // static and kinetic coefficients
inline constexpr double kUnusualFriction = 2.0;   // above: accepted with a warning
inline constexpr double kMaxRotationalFriction = 100.0;  // N m s
inline constexpr double kMaxSpeed = 100.0;        // m/s: a hand, the base or the hoist between steps
inline constexpr double kMinRate = 1.0;           // Hz: the fixed step rate
inline constexpr double kMaxRate = 10000.0;       // Hz
inline constexpr double kMaxDuration = 3600.0;    // s: an input script
inline constexpr std::size_t kMaxSteps = 1'000'000;  // steps of a script or a session
inline constexpr double kMaxGravityScale = 10.0;
inline constexpr double kMaxReach = 1.0;          // m: grab reach, hoist reach, recognize and place distances
inline constexpr int kMaxSegments = 4096;         // a primitive's segments or rings
inline constexpr int kMaxGroupDepth = 32;         // groups nested in a scene
inline constexpr int kMaxJsonDepth = 100;         // arrays and objects nested in any JSON file
inline constexpr std::size_t kMaxJsonBytes = std::size_t{1} << 30;  // 1 GiB
// A mesh file, and the triangles of one mesh: loading 5 million triangles takes about 9 s and 1.1 GB
// (docs/benchmarks.md); twice that is the most a workstation is asked to hold.
inline constexpr std::size_t kMaxMeshFileBytes = std::size_t{2} << 30;  // 2 GiB
inline constexpr std::size_t kMaxTriangles = 10'000'000;

// What a memory-hungry task (a STEP reader or writer, a sweep's grid) may take unless told otherwise: half
// the machine's memory, MB, so that it fails with a named error before the system's out-of-memory killer
// chooses the window.
inline double defaultMemoryMB() {
  return 0.5 * static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGE_SIZE)) / 1048576.0;
}

}  // namespace vaw::limits
