#include "vaw/dynamics/integrators.hpp"

namespace vaw::dyn {

bool parseMethod(std::string_view text, Method& out) {
  for (Method m : kAllMethods)
    if (name(m) == text) {
      out = m;
      return true;
    }
  return false;
}

}  // namespace vaw::dyn
