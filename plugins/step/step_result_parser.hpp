// The STEP plugin's side of the reader's result (step_result.hpp): CBOR bytes to vaw's CAD assembly.
// Everything in the result is checked before it is used (indices in range, numbers finite, nesting
// bounded), so a result from a reader that died half-way, from another build or from a fuzzer ends in
// MalformedResult, never in a crash.
#pragma once

#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <variant>

#include "vaw/importer.hpp"

namespace vaw::step {

// What the reader reported about a bad file (its exit status 3): the fields of vaw::Diagnostic.
struct ReaderError {
  std::string field;
  std::string expected;
  std::string found;
};

class MalformedResult : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Throws MalformedResult.
std::variant<ImportedMesh, ReaderError> parseResult(std::span<const std::uint8_t> cbor);

}  // namespace vaw::step
