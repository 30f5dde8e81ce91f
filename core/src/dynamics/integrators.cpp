#include "vaw/dynamics/integrators.hpp"

namespace vaw::dyn {

std::string describe(MethodList list) {
  std::string out;
  for (std::size_t i = 0; i < list.size(); ++i) {
    if (i > 0) out += i + 1 == list.size() ? " or " : ", ";
    out += name(list[i]);
  }
  return out;
}

std::optional<Method> parseMethod(std::string_view text, MethodList list) {
  for (Method m : list)
    if (name(m) == text) return m;
  return std::nullopt;
}

}  // namespace vaw::dyn
