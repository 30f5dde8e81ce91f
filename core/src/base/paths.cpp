#include "vaw/paths.hpp"

#include <cstdlib>
#include <string_view>
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

std::filesystem::path userCacheDir() {
  if (const char* env = std::getenv("VAW_CACHE_DIR")) return std::string_view(env) == "off" ? std::filesystem::path() : std::filesystem::path(env);
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg == '/') return std::filesystem::path(xdg) / "vaw";
  if (const char* home = std::getenv("HOME"); home && *home == '/') return std::filesystem::path(home) / ".cache" / "vaw";
  return {};
}

namespace {
bool somethingAt(const std::filesystem::path& p) {
  std::error_code ec;
  const auto st = std::filesystem::symlink_status(p, ec);
  return !ec && st.type() != std::filesystem::file_type::not_found;
}
std::filesystem::path bundled(const std::filesystem::path& given) { return resourceDir() / "scenes" / given; }
}  // namespace

std::filesystem::path resolveScenePath(const std::filesystem::path& given) {
  if (given.empty() || somethingAt(given) || !given.is_relative()) return given;
  const std::filesystem::path candidate = bundled(given);
  return somethingAt(candidate) ? candidate : given;
}

std::string scenePlaces(const std::filesystem::path& given) {
  std::error_code ec;
  const std::filesystem::path absolute = std::filesystem::absolute(given, ec);
  std::string out = "looked at " + (ec ? given : absolute).string();
  if (given.is_relative()) out += " and " + bundled(given).string();
  return out;
}

std::string fileProblem(const std::filesystem::path& file) {
  std::error_code ec;
  const auto st = std::filesystem::status(file, ec);
  if (ec) {
    if (ec == std::errc::no_such_file_or_directory) return "no such file";
    if (ec == std::errc::too_many_symbolic_link_levels) return "a loop of symbolic links";
    return ec.message();
  }
  switch (st.type()) {
    case std::filesystem::file_type::regular: return {};
    case std::filesystem::file_type::not_found: return "no such file";
    case std::filesystem::file_type::directory: return "a directory";
    default: return "not a regular file";
  }
}

}  // namespace vaw
