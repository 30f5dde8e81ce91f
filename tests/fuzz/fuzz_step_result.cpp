// The STEP plugin's parser of the reader's result (plugins/step/step_result_parser.hpp) on any bytes: it may
// only return an assembly or the reader's error, or throw MalformedResult.
#include <cstdint>
#include <span>

#include "step_result_parser.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    (void)vaw::step::parseResult(std::span<const std::uint8_t>(data, size));
  } catch (const vaw::step::MalformedResult&) {
  }
  return 0;
}
