// The key under which the reader's result of a STEP file is kept for reopening (vaw/kept_results.hpp,
// docs/step.md "Reopening a file"): a hash of the file's bytes, the result's format version, the
// tessellation, the instance limit and the reader's own build.
#pragma once

#include <filesystem>
#include <string>

#include "vaw/importer.hpp"

namespace vaw::step {

// `contentHash`: the file's bytes hashed (vaw::fileContentHash); `reader`'s build stands by its build-id.
[[nodiscard]] std::string resultKey(const std::string& contentHash, const ImportOptions& options,
                                    const std::filesystem::path& reader);

}  // namespace vaw::step
