// The key under which the reader's result of a STEP file is kept for reopening (vaw/kept_results.hpp,
// docs/step.md "Reopening a file"): a hash of the file's bytes, the result's format version, the
// tessellation, the instance limit and the reader's own build.
#pragma once

#include <filesystem>
#include <string>

#include "vaw/importer.hpp"

namespace vaw::step {

// Reads the whole file; throws vaw::InputError naming the file when it cannot. `reader`'s size and time
// stamp stand for its build.
[[nodiscard]] std::string resultKey(const std::filesystem::path& file, const ImportOptions& options,
                                    const std::filesystem::path& reader);

}  // namespace vaw::step
