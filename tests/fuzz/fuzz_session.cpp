// Sessions (docs/inputs-format.md): a session that loads is saved again and must load back the same.
#include <cstdlib>

#include "fuzz_support.hpp"
#include "vaw/sim/session.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  vaw::sim::Session s;
  try {
    s = vaw::sim::loadSession(vaw::fuzz::writeInput(data, size, "in.vaw-session.json"));
  } catch (const vaw::InputError&) {
    return 0;
  }
  const auto out = vaw::fuzz::writeInput(nullptr, 0, "out.vaw-session.json");
  vaw::sim::saveSession(s, out);
  const vaw::sim::Session back = vaw::sim::loadSession(out);  // a session vaw wrote must load
  if (back.inputs.size() != s.inputs.size() || back.scene != s.scene || back.settings.rate != s.settings.rate) std::abort();
  return 0;
}
