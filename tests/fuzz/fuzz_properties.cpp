// Part property files (docs/property-file.md).
#include "fuzz_support.hpp"
#include "vaw/error.hpp"
#include "vaw/property_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    (void)vaw::readPropertyFile(vaw::fuzz::writeInput(data, size, "part.props.json"));
  } catch (const vaw::InputError&) {
  }
  return 0;
}
