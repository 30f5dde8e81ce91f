// Writes one of the STEP test fixtures (tests/step/step_fixtures.hpp) to a file, so that command-line tests
// and benchmarks run vaw-sim on the same geometry the unit tests build:
//   vaw_write_step_fixture KIND OUTPUT.stp
// KIND: captive-ring, bolted-rod (clean), bolted-rod-split4 (cylinders in quarters, B-spline faces) or
// bolted-rod-proe (AP203 in inches, Y up, cylinders in halves, names on the products only), or tiled-XxY
// (writeTiledProduct: tiled-9x6 is the 1,027-part product), or rig-XxY (writeRigProduct: rig-7x4 is 981
// parts).
#include <cstdio>
#include <exception>
#include <string>

#include "step_fixtures.hpp"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr,
                 "usage: vaw_write_step_fixture "
                 "captive-ring|bolted-rod|bolted-rod-split4|bolted-rod-proe|fastened-block[-inch|-clash]|bearing-in-housing|"
                 "keyed-hub[-inch]|unsewn-and-hollow|tiled-XxY|rig-XxY OUTPUT.stp\n");
    return 2;
  }
  const std::string kind = argv[1];
  try {
    using vaw::steptest::ExportStyle;
    if (kind == "captive-ring") vaw::steptest::writeCaptiveRing(argv[2]);
    else if (kind == "bolted-rod") vaw::steptest::writeBoltedRod(argv[2]);
    else if (kind == "bolted-rod-split4") vaw::steptest::writeBoltedRod(argv[2], ExportStyle{4, true, true, false, false, "AP214"});
    else if (kind == "fastened-block") vaw::steptest::writeFastenedBlock(argv[2]);
    else if (kind == "fastened-block-inch") vaw::steptest::writeFastenedBlock(argv[2], {true, false, false});
    else if (kind == "fastened-block-clash") vaw::steptest::writeFastenedBlock(argv[2], {false, false, true});
    else if (kind == "bearing-in-housing") vaw::steptest::writeBearingInHousing(argv[2]);
    else if (kind == "keyed-hub") vaw::steptest::writeKeyedHub(argv[2]);
    else if (kind == "keyed-hub-inch") vaw::steptest::writeKeyedHub(argv[2], {true, false, false});
    else if (kind == "unsewn-and-hollow") vaw::steptest::writeUnsewnAndHollow(argv[2]);
    else if (kind == "bolted-rod-proe") vaw::steptest::writeBoltedRod(argv[2], ExportStyle{2, false, false, true, true, "AP203"});
    else if (int x = 0, y = 0; std::sscanf(kind.c_str(), "tiled-%dx%d", &x, &y) == 2) vaw::steptest::writeTiledProduct(argv[2], x, y);
    else if (int rx = 0, ry = 0; std::sscanf(kind.c_str(), "rig-%dx%d", &rx, &ry) == 2) vaw::steptest::writeRigProduct(argv[2], rx, ry);
    else {
      std::fprintf(stderr, "vaw_write_step_fixture: unknown kind \"%s\"\n", kind.c_str());
      return 2;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "vaw_write_step_fixture: %s\n", e.what());
    return 1;
  }
  return 0;
}
