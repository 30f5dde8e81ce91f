#pragma once
// Errors for bad user input. Every one names the file, the field inside it and what was expected,
// so a person can fix the file without reading our code (docs/architecture.md, "Errors by audience").
#include <stdexcept>
#include <string>
#include <vector>

namespace vaw {

struct Diagnostic {
  enum class Severity { Warning, Error };
  Severity severity = Severity::Error;
  std::string file;      // path as the user gave it (or the resolved path)
  std::string field;     // JSON-pointer-like path, e.g. "parts[2].density", or a mesh check name
  std::string expected;  // what a valid value looks like
  std::string found;     // what was there (may be empty)

  [[nodiscard]] std::string message() const;
};

class InputError : public std::runtime_error {
 public:
  explicit InputError(Diagnostic d);
  [[nodiscard]] const Diagnostic& diagnostic() const noexcept { return d_; }

 private:
  Diagnostic d_;
};

// An output file that could not be written (full disk, file-size limit, no permission): the message
// names the file and the system's reason.
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

[[noreturn]] void fail(std::string file, std::string field, std::string expected, std::string found = {});

using Diagnostics = std::vector<Diagnostic>;

}  // namespace vaw
