#include "vaw/error.hpp"

namespace vaw {

std::string Diagnostic::message() const {
  std::string m = file.empty() ? std::string("<input>") : file;
  if (!field.empty()) m += ": " + field;
  // A note that names no expectation (a reader's warning passed on) is said as it is.
  if (expected.empty()) return m + ": " + found;
  m += ": expected " + expected;
  if (!found.empty()) m += ", found " + found;
  return m;
}

InputError::InputError(Diagnostic d) : std::runtime_error(d.message()), d_(std::move(d)) {}

void fail(std::string file, std::string field, std::string expected, std::string found) {
  throw InputError(Diagnostic{Diagnostic::Severity::Error, std::move(file), std::move(field),
                              std::move(expected), std::move(found)});
}

}  // namespace vaw
