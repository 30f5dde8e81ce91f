// Input scripts (docs/inputs-format.md), sampled at their rate.
#include "fuzz_support.hpp"
#include "vaw/sim/session.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    vaw::sim::Settings settings;
    (void)vaw::sim::loadInputScript(vaw::fuzz::writeInput(data, size, "script.vaw-inputs.json"), settings);
  } catch (const vaw::InputError&) {
  }
  return 0;
}
