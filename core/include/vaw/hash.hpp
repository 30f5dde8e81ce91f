#pragma once
// FNV-1a 64 over raw bytes: the determinism checks of the world and the scene's content hash. Not for
// security; stable across runs and machines of one byte order.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

namespace vaw {

inline constexpr std::uint64_t kFnvOffset = 0xcbf29ce484222325ULL;

inline std::uint64_t fnv1a(const void* data, std::size_t size, std::uint64_t h = kFnvOffset) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) {
    h ^= p[i];
    h *= 0x100000001b3ULL;
  }
  return h;
}

inline std::uint64_t fnv1a(std::string_view s, std::uint64_t h) { return fnv1a(s.data(), s.size(), h); }

// A hash as text, 16 hex digits: as sessions store the scene's, and as kept results are named.
inline std::string hashText(std::uint64_t hash) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(hash));
  return buf;
}

}  // namespace vaw
