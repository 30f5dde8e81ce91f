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

// How CAD systems write what the clean fixtures above do not (docs/step.md, "Files as CAD systems write
// them"): closed faces divided at seams, every face a B-spline, names only on the products (the
// instances unnamed, so Open CASCADE calls them "=>[0:1:1:N]"), inches, a model built with Y up.
struct ExportStyle {
  int splits = 1;               // each closed face (cylinder) divided into this many faces: 1, 2 or 4
  bool bsplineFaces = false;    // then every face written as a B-spline
  bool namedInstances = true;   // false: the components carry no name of their own
  bool yUp = false;             // the assembly modelled with +Y up (the model's +Z written as the file's +Y)
  bool inches = false;
  std::string schema = "AP214";
};

// A bolted rod assembly (mm, Z up before `yUp`): the base "PLATE" (200 x 100 x 10, six through holes
// r 4.25 at z 0..10), two "L-BRACKET"s on it (the second turned 180 degrees), each held by three headed
// "BOLT"s (shank r 4 from 12 mm below the plate to the flange's top at z 18, head r 6.5 above it) with a
// "NUT" under the plate (r 4..7, z -8..0), and a "ROD" (r 5, x 60..140 at y 50, z 40) through both
// brackets' uprights (bores r 5.25), a "ROD-NUT" (r 5..8, 8 long) against each upright's outer face.
// Products are named as in quotes; with `namedInstances` the instances are "plate", "bracket-1/2",
// "bolt-1".."bolt-6" (bracket 1's first), "nut-1".."nut-6" (under bolt k), "rod", "rod-nut-1/2". 22 inserts
// and 16 mates in all (tests/step/step_fixtures.cpp has every coordinate).
void writeBoltedRod(const std::filesystem::path& file, const ExportStyle& style = {});

// A product of `tilesX` x `tilesY` repeated sub-assemblies on one base, as large products are built: the
// "BASE-PLATE" (10 thick, top at z 10, a tile every 210 mm in x and 110 in y) with each tile's six bolt holes
// (r 4.25) and four dowel holes (r 3.2), and under the root one "TILE" sub-assembly per tile ("tile-1",
// row by row): the bolted rod's brackets, bolts, nuts and rod (bracket-1/2, bolt-1..6, nut-1..6, rod,
// named and placed as in writeBoltedRod; no rod nuts) and "dowel-1".."dowel-4" (r 3, z 2..24). 19 parts a
// tile, 24 inserts and 14 mates. 9 x 6 tiles make 1,027 parts with 540 holes in a 1.9 m plate.
// With `emptyHoles`, each tile's plate area has two more through holes (r 4.25 at (100, 40) and (100, 60) of
// the tile) that nothing goes into, as a base drilled for options has.
void writeTiledProduct(const std::filesystem::path& file, int tilesX, int tilesY, bool emptyHoles = false);

// A large product unlike the tiled one, built as a test rig is (mm, Z up; step_fixtures.cpp has every
// coordinate): the "RIG-PLATE" (12 thick, top at z 0, 400 x 300 a tile) with `tilesX` x `tilesY` tiles, the
// whole product placed far from the file's origin (at (2500, 1200, 750)) and the plate's own frame at its
// centre. Each "RIG-TILE" sub-assembly holds two "BRACKET-ASSEMBLY"s (an L-bracket with a bored upright,
// four headed bolts from above through the flange and the plate, r 5 in r 5.25 holes, a nut under the plate
// on each), two "COVER-ASSEMBLY"s (a cover plate held by two bolts from below, heads under the plate, nuts on
// the cover), a "ROD-ASSEMBLY" (a rod through both uprights' bores with two collars between them) and four
// "RIG-PIN" dowels (r 4) in blind holes (8 deep) of the plate through the covers; and the plate has five
// holes a tile that nothing goes into (three through, two blind). 35 parts a tile: 7 x 4 tiles make 981.
void writeRigProduct(const std::filesystem::path& file, int tilesX, int tilesY);

// An assembly modelled the way designers model fasteners and fits (mm, Z up; step_fixtures.cpp has every
// coordinate): the "BASE" block (120 x 80 x 20, top edges chamfered) with two tapped M6 holes modelled at
// the tap drill (r 2.5, 14 deep, a 118 degree drill point) and two dowel holes (r 3, 8 deep); the
// "BRACKET" (60 x 40 x 15, vertical edges filleted r 3) on it, held by two "ISO 4762 M6x20" cap screws
// (shank r 3 at nominal, head r 5 x 6, tips and heads chamfered) in counterbores (r 3.2 through, r 5.5 x
// 6.5), located by two "ISO 8734 6x16" dowels (r 3.003: pressed into the base, a clearance of 7 um in the
// bracket); the "COVER" (50 x 34 x 4) on the bracket over the cap screws, held by two "ISO 10642 M5x12"
// countersunk screws (90 degree heads flush in countersinks) in the bracket's tapped M5 holes (r 2.1) at
// (+-15, +-9) from the middle.
// Instances: base, bracket, cover, cap-screw-1/2, dowel-1/2, csk-screw-1/2. 12 inserts (4 threaded, 2
// press) and 6 mates.
struct DesignerStyle {
  bool inches = false;
  bool bsplineFaces = false;
  // dowel-1 r 3.3 in its r 3 hole: neither a press fit nor a thread, a clash of the modelling.
  bool clash = false;
};
void writeFastenedBlock(const std::filesystem::path& file, const DesignerStyle& style = {});
// The exact volume (mm^3) two of its instances share where the file places them, from Open CASCADE's
// boolean common of their solids: the reference the interference check is measured against.
double fastenedBlockOverlap(const std::string& a, const std::string& b, const DesignerStyle& style = {});
// A hub keyed on a shaft as designers model it (mm, Z up): the "SHAFT" (r 10, 60 long) standing in a blind
// bore (r 10, 10 deep) of the "BASE" block (120 x 120 x 15), with a keyway 3.5 deep, a closed pocket with
// round ends 35..55 along the shaft; a "DIN 6885 A 6x6x20" feather key (6 wide, 6 high, round ends) in it;
// the "HUB" (r 10.01 .. 25, 20 long) over both, its slot 6 wide through its length, 0.3 above the key.
// Chamfered edges. Instances: base, shaft, key, hub.
void writeKeyedHub(const std::filesystem::path& file, const DesignerStyle& style = {});
// A ball bearing as CAD libraries model it, a sub-assembly "BEARING-608" of an inner ring (r 4..6.5), an
// outer ring (r 9..11, both 7 wide with a groove for the balls) and 8 balls (r 1.75 at r 7.75), seated in a
// "HOUSING" block's bore (r 11, 7 deep), with a "SHAFT" (r 4, 30 long) through its inner ring. The
// instances: housing, bearing (ring-inner, ring-outer, ball-1..8), shaft.
void writeBearingInHousing(const std::filesystem::path& file);
// A part of 6 faces that share no edges (as some exporters leave a solid: unsewn), "UNSEWN-BOX" 40 x 30 x 20,
// beside a "HOLLOW-BOX" 40 x 40 x 40 with a closed void 20 x 20 x 20 at its centre.
void writeUnsewnAndHollow(const std::filesystem::path& file);

// `text` (a STEP file's) with its first NEXT_ASSEMBLY_USAGE_OCCURRENCE written `copies` times more, under new
// entity numbers from 900000: that many more instances of one product, the "instance bomb" the reader's
// first pass refuses. Throws std::invalid_argument when the text has no such entity.
std::string withMoreUses(const std::string& text, int copies);

}  // namespace vaw::steptest
