// Writes the bundled STEP sample, the bolted bracket of the STEP tests (tests/step/step_fixtures.hpp),
// so the sample and the tests' expectations are one geometry. Output committed as
// resources/step/bolted-bracket.stp; run from the repository root:
//   vaw_make_step_sample resources/step/bolted-bracket.stp
#include <cstdio>
#include <exception>

#include "step_fixtures.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: vaw_make_step_sample OUTPUT.stp\n");
    return 2;
  }
  try {
    vaw::steptest::writeBoltedBracket(argv[1]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "vaw_make_step_sample: %s\n", e.what());
    return 1;
  }
  return 0;
}
