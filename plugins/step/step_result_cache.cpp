#include "step_result_cache.hpp"

#include <cstdint>

#include "vaw/kept_results.hpp"

#include "step_result.hpp"

namespace vaw::step {

std::string resultKey(const std::string& contentHash, const ImportOptions& options, const std::filesystem::path& reader) {
  // Another build of the reader may read the same file differently.
  return ResultKey(buildIdentity(reader))
      .add(std::string_view(contentHash))
      .add(kResultVersion)
      .add(options.relativeDeflection)
      .add(options.angularDeflection)
      .add(options.maxInstances)
      .text();
}

}  // namespace vaw::step
