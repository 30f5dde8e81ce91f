#pragma once
// STEP files for tests and samples, written with Open CASCADE itself so that the geometry, and so every
// expected volume, centroid and location, is known exactly (docs/step.md).
#include <filesystem>
#include <string>

namespace vaw::steptest {

struct FixtureOptions {
  bool inches = false;           // the file's length unit is the inch (Open CASCADE converts on write)
  bool bsplineFaces = false;     // every face written as a B-spline, as some exporters do
  bool wireframeBeside = false;  // adds "construction-lines" (edges only) and "empty-rep" (an empty shape)
  std::string schema = "AP214";  // "AP203", "AP214" or "AP242"
};

// The bolted bracket: plate, bracket, two studs, two nuts and a pin assembly (pin and sleeve), 8 part
// instances under the root "bolted-bracket" (tests/step/step_fixtures.cpp has the exact geometry).
void writeBoltedBracket(const std::filesystem::path& file, const FixtureOptions& options = {});
// `count` instances in all (a base plate with studs, nuts, pins and sleeves in a grid), for benchmarks:
// four shared products, or with `distinctProducts` a product of its own for every part.
void writeManyParts(const std::filesystem::path& file, int count, bool distinctProducts = false);
// Two boxes 20 mm cubes that touch only along one edge (a pair that must give no constraint).
void writeEdgeTouchingBoxes(const std::filesystem::path& file);
// A peg in a blind hole of a plate under a cover that hides it: the peg can only go in before the cover
// ("plate", "peg", "cover"; the peg's top 3 mm under the cover's pocket ceiling).
void writePegUnderCover(const std::filesystem::path& file);
// A ring on a base whose shaft has a flange at its top: the ring can come home along its axis from neither
// end ("base", "ring", and a free "cap" on the flange).
void writeCaptiveRing(const std::filesystem::path& file);

}  // namespace vaw::steptest
