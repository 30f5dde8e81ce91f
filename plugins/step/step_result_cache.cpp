#include "step_result_cache.hpp"

#include <cstdint>

#include "vaw/hash.hpp"
#include "vaw/kept_results.hpp"

#include "step_result.hpp"

namespace vaw::step {

namespace {
template <typename T>
std::uint64_t mix(const T& value, std::uint64_t h) {
  return fnv1a(&value, sizeof value, h);
}
}  // namespace

std::string resultKey(const std::string& contentHash, const ImportOptions& options, const std::filesystem::path& reader) {
  std::uint64_t h = fnv1a(contentHash, kFnvOffset);
  h = mix(kResultVersion, h);
  h = mix(options.relativeDeflection, h);
  h = mix(options.angularDeflection, h);
  h = mix(options.maxInstances, h);
  // Another build of the reader may read the same file differently.
  h = mix(buildIdentity(reader), h);
  return hashText(h);
}

}  // namespace vaw::step
