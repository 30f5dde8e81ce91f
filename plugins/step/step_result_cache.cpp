#include "step_result_cache.hpp"

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <vector>

#include "vaw/error.hpp"
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

std::string resultKey(const std::filesystem::path& file, const ImportOptions& options, const std::filesystem::path& reader) {
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file.string(), "", "an existing, readable file", std::strerror(errno));
  std::uint64_t h = kFnvOffset, size = 0;
  std::vector<char> buf(1 << 20);
  while (in) {
    in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
    const auto n = static_cast<std::size_t>(in.gcount());
    h = fnv1a(buf.data(), n, h);
    size += n;
  }
  if (in.bad()) fail(file.string(), "", "a file that can be read to its end", std::strerror(errno));
  h = mix(size, h);
  h = mix(kResultVersion, h);
  h = mix(options.relativeDeflection, h);
  h = mix(options.angularDeflection, h);
  h = mix(options.maxInstances, h);
  // Another build of the reader may read the same file differently.
  h = mix(buildIdentity(reader), h);
  return hashText(h);
}

}  // namespace vaw::step
