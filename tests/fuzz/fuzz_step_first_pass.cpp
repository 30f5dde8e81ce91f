// The STEP reader's first pass (plugins/step/step_first_pass.hpp) on any text: it may only accept the text
// or refuse it with FirstPassRefusal, and a rewritten text keeps every line.
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "step_first_pass.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const auto r = vaw::step::firstPass(text);
    if (r.rewritten > 0 && std::count(r.text.begin(), r.text.end(), '\n') != std::count(text.begin(), text.end(), '\n'))
      std::abort();
  } catch (const vaw::step::FirstPassRefusal&) {
  }
  return 0;
}
