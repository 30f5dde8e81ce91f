#include "vaw/paths.hpp"

#include <cstdlib>
#include <system_error>

namespace vaw {

std::filesystem::path executableDir() {
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::filesystem::current_path() : exe.parent_path();
}

std::filesystem::path resourceDir() {
  if (const char* env = std::getenv("VAW_RESOURCE_DIR"); env && *env) return env;
  return (executableDir() / ".." / "share" / "vaw").lexically_normal();
}

std::filesystem::path defaultScenePath() { return resourceDir() / "scenes" / "sleeve-on-shaft.vaw.json"; }

}  // namespace vaw
